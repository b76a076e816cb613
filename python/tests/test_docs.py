"""docs/python.md's examples, run as written: every ```python block, in order, in one
namespace per section, in a scratch directory (blocks fenced ```python no-run are shown
only). A figure an example saves must exist afterwards."""

import os
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

DOC = Path(os.environ.get("SLIDESPEC_DOCS", Path(__file__).resolve().parents[2] / "docs")) / "python.md"


def sections():
    """(title, [code blocks]) per '## ' section of the page."""
    found, title = [], None
    for part in re.split(r"^## ", DOC.read_text(), flags=re.M)[1:]:
        title = part.splitlines()[0]
        blocks = re.findall(r"^```python\n(.*?)^```", part, flags=re.M | re.S)
        if blocks:
            found.append((title, blocks))
    return found


def test_the_page_has_its_examples():
    titles = [title for title, _ in sections()]
    assert any("parameter study" in t for t in titles) and any("Fitting" in t for t in titles)


def test_examples_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for title, blocks in sections():
        namespace = {"__name__": "__docs__"}
        for block in blocks:
            exec(compile(block, f"{DOC.name}: {title}", "exec"), namespace)
        for figure in re.findall(r'savefig\("([^"]+)"', "".join(blocks)):
            assert (tmp_path / figure).stat().st_size > 10000, figure
