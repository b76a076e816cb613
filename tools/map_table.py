"""What the map plots of docs/model.md §7 share: reading a map program's TSV and saving a
figure atomically."""

import os
import tempfile

import numpy as np


def rows(path, columns, program):
    """The rows of a map TSV, each its fields as text. ValueError names the file when its
    header is not `columns`."""
    with open(path) as f:
        lines = [line.rstrip("\n").split("\t") for line in f if line.strip()]
    if not lines or tuple(lines[0]) != columns:
        raise ValueError(f"{path}: not a {program} table (header {columns})")
    return lines[1:]


def read(path, columns, program):
    """Rows of a map TSV by their first column (the renewal kind), as column arrays."""
    by_kind = {}
    for fields in rows(path, columns, program):
        by_kind.setdefault(fields[0], []).append([float(x) for x in fields[1:]])
    return {kind: dict(zip(columns[1:], np.array(r).T)) for kind, r in by_kind.items()}


def save(fig, out):
    """Write the figure to `out` through a temporary file beside it, so that `out` is either
    the old image or the whole new one."""
    handle, temporary = tempfile.mkstemp(suffix=".png", dir=os.path.dirname(os.path.abspath(out)))
    os.close(handle)
    try:
        fig.savefig(temporary, dpi=90)
        os.replace(temporary, out)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)
