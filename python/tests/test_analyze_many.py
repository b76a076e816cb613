"""ss.analyze_many: record files analysed as `slidespec analyze A B C` analyses them, a file
refused without stopping the rest, and the combined table the command writes."""

import json
import subprocess
import warnings

import numpy as np
import pytest

import slidespec as ss
from test_module import CLI, bits


def synth(out, *options):
    done = subprocess.run([CLI, "synth", "--case", "fast", "--set", "alpha=0.4", "--sample-interval", "0.01",
                           "--resolution", "0", "--sensor-noise", "0", *options, "--out", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return f"{out}.csv"


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """A plain record, a reciprocating one, one of velocity steps, a malformed one and a
    directory: in the order the command line is given them."""
    folder = tmp_path_factory.mktemp("records")
    bad = folder / "bad.csv"
    bad.write_text("t,x\n0,1\n0.001,abc\n")
    (folder / "a_directory").mkdir()
    return [synth(folder / "plain", "--duration", "200"),
            synth(folder / "strokes", "--strokes", "8", "--stroke-length", "50mm", "--dwell", "1"),
            str(bad), str(folder / "a_directory"),
            synth(folder / "steps", "--program", "1:100,0:2,3:100")]


def test_the_table_is_the_command_lines_to_the_last_bit(records, tmp_path):
    done = subprocess.run([CLI, "analyze", *records, "--fit-slope", "8", "30", "--no-plot", "--quiet",
                           "--out", str(tmp_path / "many")], capture_output=True, text=True)
    assert done.returncode == 3, done.stderr
    expected = json.loads((tmp_path / "many.json").read_text())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results, table = ss.analyze_many(records, fit_slope=(8, 30))
    assert all(str(w.message).startswith(tuple(f"{path}: " for path in records)) for w in caught)
    got = table.to_dict()
    assert got["named"] == expected["named"] == 5 and len(table) == 5
    for row, want in zip(got["records"], expected["records"]):
        want.pop("outputs")
        if not want["ok"]:  # the command line's words for an option; no option is named here
            assert "--" not in want["reason"]
        assert bits(row) == bits(want), row["file"]
    assert list(table.segment) == ["whole", "strokes", None, None, "sliding"]
    assert table.strokes.tolist() == [0, 8, 0, 0, 0] and table.ok.tolist()[2:4] == [False, False]
    # Each analysed record's own result is its PREFIX.json's fields, file included.
    plain = json.loads((tmp_path / "many_plain.json").read_text())
    del plain["points"]
    mine = results[0].to_dict()
    del mine["points"]
    assert bits(mine) == bits(plain)
    assert results[1].strokes["count"] == 8 and results[1].slope == table.slope[1]


def test_a_file_refused_carries_why_and_the_rest_go_on(records):
    results, table = ss.analyze_many(records[2:4] + records[:1], fit_slope=(8, 30))
    bad, directory, plain = results
    assert not bad.ok and bad.reason.startswith(records[2] + ": line 3") and bad.record["file"] == records[2]
    assert not directory.ok and directory.reason == records[3] + ": a directory, not a record"
    assert plain.ok and len(plain) > 10
    assert table.reason[:2] == [bad.reason, directory.reason] and np.isnan(table.v[:2]).all()
    assert table.v[2] == plain.mean_speed


def test_keywords_no_record_satisfies_are_refused_before_any_file(tmp_path):
    missing = str(tmp_path / "missing.csv")
    with pytest.raises(ValueError, match="^fit alpha needs compare NAME$"):
        ss.analyze_many([missing], fit="alpha")
    with pytest.raises(ValueError, match="^force: a file's channel is its column"):
        ss.analyze_many([missing], force=np.ones(3))
    with pytest.raises(TypeError, match="'x'"):
        ss.analyze_many([missing], x=np.ones(3))
    results, table = ss.analyze_many(missing)
    assert results[0].reason == missing + ": no such file" and table.ok.tolist() == [False]
