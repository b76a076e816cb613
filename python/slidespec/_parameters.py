"""The model's parameters: named cases, overrides, the parameter table."""

import re as _re
from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _core


_PARAMETERS = {row["key"]: row for row in _core.parameter_table()}
# Keyword defaults, the command line's own (run's band, precision and seed; synth's sensor).
_RUN = _core.run_defaults
_SENSOR = _core.sensor_defaults


# Parameters.landmarks's doc, from the rows of include/slidespec/landmarks.def.
_LANDMARKS_DOC = "The theory's landmarks {key: value}, SI units (docs/model.md §4):\n" + "".join(
    f"    {row['key']}: {row['doc']}" + (' (with drive="spring" only)' if row["python"] == "with_spring" else "")
    + "\n" for row in _core.landmark_table() if row["python"] != "never")


def parameter_table():
    """The model's parameters (docs/model.md §2), one dict each, in display order: key,
    kind ("count", "real", "word" or "levels"), unit (SI, "" for none), symbol (as figures
    write it: "*η*_{0}" for eta0, *italic* and _{subscript}), allowed (its range or words), per_level (KEY_l sets level l of a tree), doc, words, reference (the
    reference case's value, as text)."""
    return [dict(row) for row in _PARAMETERS.values()]


def _kind(key):
    """The kind of KEY or KEY_l (None for a key that is not a parameter)."""
    row = _PARAMETERS.get(key) or _PARAMETERS.get(_re.sub(r"_\d+$", "", key))
    return row["kind"] if row else None


def _typed(key, value):
    """A parameter value as Python meets it: int for counts, str for names, else float."""
    if not isinstance(value, str):
        return value
    kind = _kind(key)
    if kind == "count":
        return int(float(value))
    if kind == "real":
        return float(value)
    return value


def _text(key, value):
    """A Python value as the library parses it (repr keeps every bit of a float)."""
    if isinstance(value, bool):
        raise ValueError(f"parameter {key}: {value!r} is not a number")
    if isinstance(value, str):
        return value
    if not isinstance(value, (list, tuple, _np.ndarray, int, float, _np.integer, _np.floating)):
        raise ValueError(f"parameter {key}: {value!r} ({type(value).__name__}) is neither a number nor a word (str)")
    if isinstance(value, (list, tuple, _np.ndarray)):
        # Only a list of levels (touching) is a list; a parameter's number in one is a mistake.
        if _kind(key) != "levels":
            raise ValueError(f"parameter {key}: {value!r} is a list; give one value")
        return ",".join(_text(key, v) for v in value)
    if isinstance(value, (int, _np.integer)):
        return str(int(value))
    return repr(float(value))


def cases(descriptions=False):
    """Names of the paper's cases (the reference case and its variants).

    With descriptions=True, a dict {name: description}. Parameters(name).to_dict() gives
    a case's values."""
    found = _core.cases()
    if descriptions:
        return {name: description for name, description, _ in found}
    return [name for name, _, _ in found]


class Parameters(_Mapping):
    """A validated parameter set of the model: a named case plus overrides.

        p = Parameters("reference", alpha=0.4, N=12)
        p["alpha"], p["eta1"]         # every key, derived ones too
        p.to_dict()                   # {key: value}, JSON-serialisable

    Keys and units (docs/model.md §2; parameter_table() gives them as data; blocks on
    blocks in docs/hierarchy.md):
    {keys}
    Give v or eta1; the other is derived (an eta1 given beside the v it derives from is
    dropped, so Parameters(**p.to_dict()) is p). A bad key or value raises ValueError naming it.
    """

    __doc__ = __doc__.replace("{keys}", "\n    ".join(
        f"{row['key']}: {row['doc']}" + (f" [{row['unit']}]" if row["unit"] else "")
        + (f" (KEY_l for level l)" if row["per_level"] else "") for row in _PARAMETERS.values()))

    def __init__(self, case="reference", /, **overrides):
        self._case = str(case)
        if "v" in overrides and "eta1" in overrides:
            # eta1 listed beside the v it was derived from (to_dict(), Result.parameters): as
            # the command's --params, v is kept; an eta1 that v does not give stays an error.
            derived = Parameters(case, **{key: value for key, value in overrides.items() if key != "eta1"})
            if _typed("eta1", _text("eta1", overrides["eta1"])) == derived["eta1"]:
                overrides = {key: value for key, value in overrides.items() if key != "eta1"}
        self._overrides = tuple((key, _text(key, value)) for key, value in overrides.items())
        self._values = {key: _typed(key, value)
                        for key, value in _core.describe(self._case, list(self._overrides))}

    @classmethod
    def from_dict(cls, values, case="reference"):
        """Parameters from a {key: value} dict such as to_dict() or Result.parameters
        gives; eta1 is dropped when v is there (it is derived from v)."""
        values = dict(values)
        if "v" in values:
            values.pop("eta1", None)
        return cls(case, **values)

    @property
    def case(self):
        """The named case the overrides apply to."""
        return self._case

    @property
    def overrides(self):
        """The keys set over the case, as given (text as the library parsed it)."""
        return dict(self._overrides)

    def replace(self, **changes):
        """A copy with some keys changed: p.replace(alpha=0.5)."""
        merged = dict(self._overrides)
        merged.update((key, _text(key, value)) for key, value in changes.items())
        return Parameters(self._case, **merged)

    def to_dict(self):
        """Every parameter {key: value} (int, float or str), JSON-serialisable."""
        return dict(self._values)

    def _landmarks(self):
        return _core.landmarks(self._case, list(self._overrides))

    landmarks = property(_landmarks, doc=_LANDMARKS_DOC)

    def __getitem__(self, key):
        try:
            return self._values[key]
        except KeyError:
            raise KeyError(f"{key!r} is not a parameter (known: {' '.join(self._values)})") from None

    def __iter__(self):
        return iter(self._values)

    def __len__(self):
        return len(self._values)

    def __eq__(self, other):
        return isinstance(other, Parameters) and self._values == other._values

    def __hash__(self):
        return hash(tuple(self._values.items()))

    def __repr__(self):
        args = "".join(f", {key}={_typed(key, value)!r}" for key, value in self._overrides)
        return f"Parameters({self._case!r}{args})"

    def __reduce__(self):
        return (_rebuild_parameters, (self._case, self._overrides))

    def _args(self):
        return self._case, list(self._overrides)


def _rebuild_parameters(case, overrides):
    return Parameters(case, **dict(overrides))


def _as_parameters(params):
    if isinstance(params, Parameters):
        return params
    if isinstance(params, str):
        return Parameters(params)
    raise TypeError(f"expected slidespec.Parameters or a case name, got {type(params).__name__}")
