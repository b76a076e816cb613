"""Results: the command line's document as fields, its points as numpy columns."""

import json as _json
import math as _math

import numpy as _np

from ._parameters import _typed


def _columns(points):
    """A list of point dicts as {name: column}: numbers as numpy arrays (whole numbers as
    int64, as the document types them; None as NaN), nested dicts as dicts of columns,
    words as lists."""
    if not points:
        return {}
    columns = {}
    for key in points[0]:
        values = [point.get(key) for point in points]
        if all(isinstance(v, dict) for v in values):
            columns[key] = _columns(values)
        elif all(isinstance(v, bool) for v in values):
            columns[key] = _np.array(values, dtype=bool)
        elif all(isinstance(v, int) and not isinstance(v, bool) for v in values):
            columns[key] = _np.array(values, dtype=_np.int64)
        elif all(isinstance(v, (int, float)) or v is None for v in values):
            columns[key] = _np.array([_math.nan if v is None else v for v in values], dtype=float)
        else:
            columns[key] = list(values)
    return columns


def _shown(column):
    """A column as an attribute gives it: numbers as floats."""
    if isinstance(column, dict):
        return {key: _shown(values) for key, values in column.items()}
    if isinstance(column, _np.ndarray) and column.dtype.kind in "iu":
        return column.astype(float)
    return column


def _point(columns, k):
    """Point k of the columns as the document holds it: Python numbers, None for inf and nan."""
    point = {}
    for name, values in columns.items():
        if isinstance(values, dict):
            point[name] = _point(values, k)
            continue
        value = values[k]
        value = value.item() if isinstance(value, _np.generic) else value
        point[name] = None if isinstance(value, float) and not _math.isfinite(value) else value
    return point


class _Table:
    """A result: the fields of the command line's JSON document (`data`, without its points)
    and its points as columns. Fields the library adds flow through: every column is an
    attribute."""

    def __init__(self, data, state=None, columns=None):
        """data: the document's fields (and its "points", read from a file); columns: the
        points as {name: numpy array}, as the binding gives them."""
        self._data = {key: value for key, value in data.items() if key != "points"}
        self._state = state
        self._points = _columns(data.get("points", [])) if columns is None else dict(columns)
        # A per-point column named as a field of the whole result (theory_kind: the band's
        # word, and each point's) is the attribute point_NAME; the field keeps its name.
        self._columns = {("point_" + name if name in self._data else name): _shown(values)
                         for name, values in self._points.items()}

    def to_dict(self):
        """The result as the command line's PREFIX.json holds it: a JSON-serialisable dict."""
        points = [_point(self._points, k) for k in range(len(self))]
        return _json.loads(_json.dumps(self._data | {"points": points}))

    @property
    def columns(self):
        """Names of the per-point columns (each an attribute holding a numpy array; one named
        as a field of the result, as theory_kind, is point_theory_kind)."""
        return list(self._columns)

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        if name in self._columns:
            return self._columns[name]
        if name in self._data:
            return self._data[name]
        raise AttributeError(f"{type(self).__name__} has no field {name!r} "
                             f"(columns: {' '.join(self._columns)}; fields: {' '.join(self._data)})")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._columns) | set(self._data))

    def __len__(self):
        return len(self._points.get("omega", ()))

    def __getstate__(self):
        return {"data": self._data, "columns": self._points, "state": self._state}

    def __setstate__(self, saved):
        self.__init__(saved["data"], saved["state"], saved.get("columns"))


class Result(_Table):
    """A spectrum run: what `slidespec run` writes, as numpy arrays and fields.

    Columns (numpy arrays, one value per output point):
      omega [rad/s]; C_x [m^2 s] the estimate (mean of C_x over the point's FFT bins);
      stderr [m^2 s] its standard error; theory [m^2 s] the exact first-order theory seen
      through the estimator; theory_at_omega [m^2 s]; n_avg periodogram values averaged;
      bandwidth [rad/s]; theory2 [m^2 s] the theory beyond first order that theory_kind
      names (second order or quasi-static), averaged as theory is (NaN where none applies:
      see the field theory2_note); with drive="spring" the
      spring's force spectrum C_F_spring, C_F_spring_stderr, C_F_spring_theory [N^2 s]
      (k_drive^2 times C_x, stderr, theory); and any column the library or the file adds
      (see `columns`).
    Fields: complete (False when interrupted), reached_precision (largest stderr/C_x),
      mean_speed and mean_speed_error [m/s], simulated_time [s], wall_seconds [s],
      theory_kind (the best theory that holds here, docs/model.md §7.4: "second_order" is the
      column theory2, "first_order" the column theory, "none" neither) and theory_kind_note,
      parameters {key: value}, case, request, sub_bands, and every other key of the JSON.
    to_dict() gives the JSON document; results pickle. An interrupted result also holds
    its run's state: resume(result) continues it to the numbers of an unbroken run.
    """

    @property
    def omega(self):
        """Angular frequencies of the points [rad/s]."""
        return self._columns["omega"]

    @property
    def C_x(self):
        """Estimated two-sided spectrum of xi [m^2 s]."""
        return self._columns["C_x"]

    @property
    def stderr(self):
        """Standard error of C_x, from the scatter between realizations [m^2 s]."""
        return self._columns["stderr"]

    @property
    def theory(self):
        """Exact first-order theory averaged as the estimate averages it [m^2 s]."""
        return self._columns["theory"]

    @property
    def theory2(self):
        """Second-order theory (docs/model.md §7) averaged as the estimate averages it
        [m^2 s]; NaN where it does not apply (theory2_note says why)."""
        return self._columns["theory2"]

    @property
    def complete(self):
        """True when the run reached its end; False when interrupted."""
        return bool(self._data.get("complete", False))

    @property
    def mean_speed(self):
        """Measured mean sliding speed [m/s]."""
        return _value(self._data.get("measured_mean_speed"))

    @property
    def mean_speed_error(self):
        """Standard error of the measured mean sliding speed [m/s]."""
        speed = self._data.get("measured_mean_speed")
        return speed.get("standard_error") if isinstance(speed, dict) else None

    @property
    def parameters(self):
        """The run's parameters {key: value} (numbers as numbers)."""
        return {key: _typed(key, value) for key, value in self._data.get("parameters", {}).items()}

    @property
    def seed(self):
        """The run's random seed (request["seed"])."""
        return self._data.get("request", {}).get("seed")

    @property
    def state(self):
        """The saved run (bytes) of an interrupted result, for resume(); None otherwise."""
        return self._state

    def __repr__(self):
        if len(self) == 0:
            return f"<slidespec.Result {self._data.get('case', '')}: no points>"
        text = (f"<slidespec.Result {self._data.get('case', '')}: {len(self)} points "
                f"{self.omega[0]:.3g}..{self.omega[-1]:.3g} rad/s")
        if "complete" not in self._data:  # a theory table
            return text + ">"
        return (text + f", {'complete' if self.complete else 'incomplete'}, "
                f"largest stderr/C_x {self._data.get('reached_precision', _math.nan):.3g}>")


def _value(field):
    return field.get("value") if isinstance(field, dict) else field
