"""Many record files analysed alike, with one table of them all: `slidespec analyze A B C`."""

import inspect as _inspect
import os as _os

import numpy as _np

from . import _core
from ._analysis import Analysis, _analysis, _format_and_plan, analyze
from ._results import _Table

# analyze's keywords and their defaults; the arrays of one record have no place here.
_KEYWORDS = {name: parameter.default for name, parameter in _inspect.signature(analyze).parameters.items()
             if parameter.kind is _inspect.Parameter.KEYWORD_ONLY}
_ARRAYS = ("force", "normal_stress")


class Records(_Table):
    """The combined table of records analysed alike, as `slidespec analyze A B C` writes
    OUT.json. Columns, one value per record: file; segment (what was analysed: sliding,
    strokes, window, whole, or the longest stretch's kind; None when the record was refused);
    start, end [s]; v, v_err [m/s]; usable_low, usable_high [rad/s]; slope, slope_err (the
    slope fit's, else the power law's); alpha, alpha_err; strokes; ok (bool); reason (why not
    ok). A number not found is NaN. Field named: how many records were asked for."""

    def __len__(self):
        return len(self._points.get("file", ()))

    def to_dict(self):
        """The table as the command line's OUT.json holds it (without its outputs column)."""
        document = super().to_dict()
        document["records"] = document.pop("points")
        return document

    def __repr__(self):
        failed = len(self) - int(self.ok.sum()) if len(self) else 0
        return f"<slidespec.Records: {len(self)} records, {failed} not ok>"


class AnalysesInterrupted(KeyboardInterrupt):
    """Ctrl-C during analyze_many(): `results` and `table` hold the records finished before
    it, in order (fewer rows than the table's `named`); the record it cut is not among them."""

    def __init__(self, results, table):
        super().__init__(f"interrupted after {len(results)} of {table.named} records")
        self.results = results
        self.table = table


def analyze_many(paths, **keywords):
    """Each record file in `paths` analysed as analyze() analyses a record, with analyze's
    keywords (but the arrays force and normal_stress: a file's channels are its columns, named
    by their headers; units None by default, each file's header saying, else metres).

    Returns (results, table): per file an Analysis (its record's file field naming it), in
    order, and a Records table of them all. A file refused (missing, a directory, malformed,
    too short for the band) does not stop the others: its Analysis has ok False and reason,
    and its row says the same. Raises ValueError before any file is read for keywords no
    record can satisfy; warnings name the file they are of. Ctrl-C stops it within about a
    second and raises AnalysesInterrupted (a KeyboardInterrupt) holding the records finished.
    """
    if isinstance(paths, (str, bytes, _os.PathLike)):
        paths = [paths]
    paths = [_os.fspath(path) for path in paths]
    unknown = sorted(set(keywords) - set(_KEYWORDS))
    if unknown:
        raise TypeError(f"analyze_many() got an unexpected keyword argument {unknown[0]!r}")
    for name in _ARRAYS:
        if keywords.get(name) is not None and (name == "force" or _np.ndim(keywords[name]) > 0):
            raise ValueError(f"{name}: a file's channel is its column, not an array; give files whose header "
                             "names it")
    options = _KEYWORDS | {"units": None} | keywords
    record, plan = _format_and_plan(**options)
    results, rows = [], []
    analysed, interrupted = _core.analyze_files(paths, record, plan)
    for done, row in analysed:
        if done is None:
            results.append(Analysis({"ok": False, "reason": row["reason"], "record": {"file": row["file"]}}))
        else:
            results.append(_analysis(*done, stacklevel=3, about=f"{row['file']}: "))
        rows.append(row)
    table = Records({"slidespec_version": _core.version, "named": len(paths), "points": rows})
    if interrupted:
        raise AnalysesInterrupted(results, table)
    return results, table

