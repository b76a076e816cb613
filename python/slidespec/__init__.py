"""slidespec: power spectra of frictional sliding noise, from Python.

The spring-block model of Xu, Zhou and Persson: a block pulled over a rough substrate
through N miniblocks that feel kinetic friction and a random force renewed every sliding
distance ~a. slidespec gives the spectrum C_x(omega) of the sliding-distance fluctuation
xi(t) = x(t) - v t, simulated with error bars (run) or exact in first order (theory), and
analyses measured records (analyze). The numbers are those of the `slidespec` command.

Units are SI throughout: omega in rad/s (angular frequency), C_x in m^2 s (two-sided, so
that its integral over all omega is <xi^2>), lengths in m, times in s, masses in kg.

    import slidespec as ss
    p = ss.Parameters("reference", alpha=0.4)
    r = ss.run(p, omega_min=1, omega_max=1e3, precision=0.05, seed=1, progress=True)
    r.omega, r.C_x, r.stderr, r.theory          # numpy arrays [rad/s], [m^2 s]

Errors: bad parameters or requests raise ValueError with the command line's message,
naming the key; files that cannot be read raise OSError. Ctrl-C during run() raises
KeyboardInterrupt carrying what the run accumulated as `error.result`; resume() continues it.
"""

import atexit as _atexit
import errno as _errno
import json as _json
import math as _math
import os as _os
import re as _re
import stat as _stat
import threading as _threading
import time as _time
import warnings as _warnings
from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _core

__version__ = _core.version
__all__ = ["Parameters", "parameter_table", "Result", "Analysis", "cases", "omegas", "theory", "spring_force_theory", "eq1", "long_time_motion", "run", "resume",
           "read", "analyze", "synth", "PrecisionWarning", "ModelWarning", "RecordWarning"]


class PrecisionWarning(UserWarning):
    """A run ended without reaching the precision it was asked for (its work budget ran out)."""


class ModelWarning(UserWarning):
    """The parameters lie outside the first-order theory's validity, or a result is not
    what it claims (e.g. not stationary); the numbers are reported all the same."""


class RecordWarning(UserWarning):
    """A measured record's spectrum holds less than it seems, as `slidespec analyze` warns: no
    usable band (the sensor floor above the spectrum: resolution or sensor_noise in the wrong
    unit), a mean speed no friction experiment has (x in the wrong units), points the window's
    leakage may bias, or a quantization floor that is not white. The numbers are reported all
    the same."""


# ---------------------------------------------------------------------------------------
# Parameters

_PARAMETERS = {row["key"]: row for row in _core.parameter_table()}
# Keyword defaults, the command line's own (run's band, precision and seed; synth's sensor).
_RUN = _core.run_defaults
_SENSOR = _core.sensor_defaults


def parameter_table():
    """The model's parameters (docs/model.md §2), one dict each, in display order: key,
    kind ("count", "real", "word" or "levels"), unit (SI, "" for none), allowed (its range
    or words), per_level (KEY_l sets level l of a tree), doc, words, reference (the
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

    @property
    def landmarks(self):
        """The theory's landmarks: renewal_rate v/a [1/s], omega_c sqrt(N k0/M) [rad/s],
        diffusion_D [m^2/s], eq1_prefactor [m^2 rad^4/s^3], coupling_eps [-],
        forces_can_stall, outside_first_order (eps beyond the first order's measured limit, or
        stalling forces; under a spring, beyond the spring's limits), theory_kind (the best
        theory that holds: "second_order", "quasi_static", "first_order" or "none",
        docs/model.md §7.4), theory_kind_note (why no better one),
        omega_resonance [rad/s]; with drive="spring" also omega_s [rad/s] and C_x_zero,
        C_x(0) [m^2 s]."""
        return _core.landmarks(self._case, list(self._overrides))

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


# ---------------------------------------------------------------------------------------
# Theory

def omegas(omega_min=_RUN["omega_min"], omega_max=_RUN["omega_max"], points=_RUN["points"]):
    """The log-spaced angular frequencies [rad/s] of `slidespec run` and `theory`:
    `points` per decade from omega_min to omega_max inclusive, as a numpy array."""
    return _core.log_spaced_omegas(_real("omega_min", omega_min), _real("omega_max", omega_max),
                                   _whole("points", points, _MOST_INT))


def _positive_omegas(omega):
    given = _np.asarray(omega)
    if given.dtype.kind not in "iuf":
        raise TypeError(f"omega: expected numbers [rad/s], got {given.dtype.name} values")
    w = given.astype(float)
    if not _np.all(_np.isfinite(w)) or not _np.all(w > 0):
        raise ValueError("omega: every angular frequency must be a positive finite number [rad/s]")
    return w


def theory(params, omega, order=1):
    """The exact first-order spectrum C_x(omega) [m^2 s] at each omega [rad/s].

    params: Parameters or a case name. omega: a number or an array of positive angular
    frequencies [rad/s]; the result has its shape (a float for a number). The values are
    those `slidespec theory` prints (two-sided, angular: the integral over all omega is
    <xi^2>); omegas() gives the command's grid. order=2: C_x2 [m^2 s] of `slidespec theory
    --order 2`, the theory beyond first order that landmarks' theory_kind names (the
    second-order series, or the quasi-static spectrum beyond its limit; one touching level, a
    constant force, eps <= 0.25 for periodic renewal; docs/model.md section 7)."""
    p = _as_parameters(params)
    w = _positive_omegas(omega)
    values = _core.theory(*p._args(), w.ravel(), _whole("order", order, _MOST_INT)).reshape(w.shape)
    return float(values) if w.ndim == 0 else values


def spring_force_theory(params, omega):
    """drive="spring": the spring's force spectrum C_F = k_drive^2 C_x [N^2 s] at each omega
    [rad/s] (what a machine's force sensor records; docs/model.md section 9). ValueError for
    a constant force."""
    p = _as_parameters(params)
    if p.get("drive") != "spring":  # a constant-force model does not list drive
        raise ValueError("spring_force_theory: the parameters have no drive spring (set drive='spring', k_drive=...)")
    return p["k_drive"] ** 2 * theory(p, omega)


def long_time_motion(params, theory="quasi_static"):
    """The block's long-time motion: {"mean_speed": V [m/s], "diffusion": D [m^2/s]}, with
    C_x -> D / (pi omega^2) below v/a (docs/model.md section 7).

    theory: "quasi_static" (exact for the quasi-static block), "second_order" or
    "first_order"."""
    return _core.long_time_motion(*_as_parameters(params)._args(), str(theory))


def eq1(params, omega):
    """The paper's Eq. (1) asymptote prefactor / omega^4 [m^2 s] at each omega [rad/s]."""
    p = _as_parameters(params)
    w = _positive_omegas(omega)
    values = _core.eq1(*p._args(), w.ravel()).reshape(w.shape)
    return float(values) if w.ndim == 0 else values


# ---------------------------------------------------------------------------------------
# Results

def _columns(points):
    """A list of point dicts as {name: numpy array} (nested dicts as dicts of arrays)."""
    if not points:
        return {}
    columns = {}
    for key in points[0]:
        values = [point.get(key) for point in points]
        if all(isinstance(v, dict) for v in values):
            columns[key] = _columns(values)
        elif all(isinstance(v, bool) for v in values):
            columns[key] = _np.array(values, dtype=bool)
        elif all(isinstance(v, (int, float)) or v is None for v in values):
            columns[key] = _np.array([_math.nan if v is None else v for v in values], dtype=float)
        else:
            columns[key] = list(values)
    return columns


class _Table:
    """A result held as the command line's JSON document (`data`), with its points as
    numpy columns. Fields the library adds flow through: every column is an attribute."""

    def __init__(self, data, state=None):
        self._data = data
        self._state = state
        # A per-point column named as a field of the whole result (theory_kind: the band's
        # word, and each point's) is the attribute point_NAME; the field keeps its name.
        self._columns = {("point_" + name if name in data and name != "points" else name): values
                         for name, values in _columns(data.get("points", [])).items()}

    def to_dict(self):
        """The result as the command line's PREFIX.json holds it: a JSON-serialisable dict."""
        return _json.loads(_json.dumps(self._data))

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
        return len(self._data.get("points", []))

    def __getstate__(self):
        return {"data": self._data, "state": self._state}

    def __setstate__(self, saved):
        self.__init__(saved["data"], saved["state"])


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


# ---------------------------------------------------------------------------------------
# Runs

class _Progress:
    """A progress bar (tqdm: text in a terminal, a widget in a notebook) or a callback."""

    def __init__(self, progress):
        if not (isinstance(progress, bool) or callable(progress)):
            raise TypeError(f"progress: expected True, False or a callable(fraction, message), "
                            f"got {type(progress).__name__} {progress!r}")
        self._callback = progress if callable(progress) else None
        self._bar = None
        if progress is True:
            from tqdm.auto import tqdm
            self._bar = tqdm(total=100, unit="%", dynamic_ncols=True,
                             desc="run", bar_format="{desc}{percentage:5.1f}%|{bar}| [{elapsed}<{remaining}]")
        self._last = None

    def update(self, fraction, what):
        if (fraction, what) == self._last:
            return
        self._last = (fraction, what)
        if self._callback is not None:
            self._callback(fraction, what)
        if self._bar is not None:
            self._bar.n = round(100 * min(max(fraction, 0.0), 1.0), 1)
            self._bar.set_description(what or "run", refresh=False)
            self._bar.refresh()

    def close(self):
        if self._bar is not None:
            self._bar.close()


def _finish(handle):
    data = _json.loads(handle.result_json())
    result = Result(data, None if data.get("complete") else handle.save())
    stationary = data.get("stationary")
    if isinstance(stationary, dict):
        stationary = stationary.get("value", stationary.get("stationary"))
    if stationary is False:
        why = data.get("stationarity") or "see the result's 'stationary' fields"
        _warnings.warn(f"the run's spectrum is not stationary: {why}", ModelWarning, stacklevel=4)
    request = data.get("request", {})
    if (result.complete and not request.get("duration") and not request.get("realizations")
            and data.get("reached_precision", 0) > request.get("precision", _math.inf)):
        _warnings.warn(f"the precision {request['precision']} was not reached within the work "
                      f"budget of a sub-band (reached {data['reached_precision']:.3g})",
                      PrecisionWarning, stacklevel=4)
    return result


# The runs being driven, on any thread, and whether the interpreter has begun to exit.
_driven = set()
_driven_lock = _threading.Lock()
_exiting = False


@_atexit.register
def _stop_runs_at_exit():
    """At interpreter exit, stops the runs still driven on other (daemon) threads and waits
    until those threads have left slidespec's C++ code: a thread that takes the GIL back
    after the interpreter is gone is ended inside that code, which aborts the process."""
    global _exiting
    _exiting = True
    with _driven_lock:
        handles = list(_driven)
    for handle in handles:
        handle.stop()
    deadline = _time.monotonic() + 60
    while _driven and _time.monotonic() < deadline:
        _time.sleep(0.01)


def _drive(handle, threads, simd, progress):
    """Runs `handle` on its own thread while this one waits, draws progress and listens
    for Ctrl-C (the interpreter raises KeyboardInterrupt between waits of 0.1 s)."""
    with _driven_lock:
        if _exiting:
            raise RuntimeError("the interpreter is exiting: no run starts now")
        _driven.add(handle)
    try:
        bar = _Progress(progress)
        handle.start(int(threads), str(simd))
        try:
            while not handle.wait(0.1):
                bar.update(*handle.progress())
        except BaseException as error:
            handle.stop()
            handle.join()
            bar.close()
            if isinstance(error, KeyboardInterrupt):
                error.result = _finish(handle)
            raise
        handle.join()
        bar.update(1.0, "done")
        bar.close()
        return _finish(handle)
    finally:
        with _driven_lock:
            _driven.discard(handle)


def _warn_if_no_theory_holds(p):
    marks = p.landmarks
    if marks["theory_kind"] == "none":
        _warnings.warn(f"no theory holds here (theory_kind = none): {marks['theory_kind_note']}", ModelWarning,
                      stacklevel=3)


_MOST_U64 = 2**64 - 1
_MOST_INT = 2**31 - 1


def _whole(name, value, largest):
    """A count or seed as the command line takes it: an int (not bool, not float) in 0..largest."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name}: expected a whole number (int), got {type(value).__name__} {value!r}")
    if not 0 <= int(value) <= largest:
        raise ValueError(f"{name}: {value} is outside 0..{largest}")
    return int(value)


def _real(name, value):
    """A real number as the command line takes it: int or float (not bool, not text)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(value).__name__} {value!r}")
    return float(value)


def run(params, *, omega_min=_RUN["omega_min"], omega_max=_RUN["omega_max"], points=_RUN["points"],
        precision=None, duration=None, realizations=None, seed=_RUN["seed"], control_variate="shadow", threads=0,
        simd="auto", progress=False):
    """Simulates the spectrum C_x(omega) with error bars, beside the exact theory: `slidespec run`.

    params: Parameters or a case name.
    omega_min, omega_max: the band [rad/s]; points: output points per decade (log-spaced).
    precision: target standard error / C_x at every point (0 < precision < 1, default 0.05);
      realizations are added until every point reaches it or a sub-band's work budget is spent.
    duration: instead (not with precision), a fixed simulated time per realization of the lowest sub-band [s].
    realizations: a fixed number of realizations per sub-band.
    control_variate: "shadow" (each realization's linear shadow as a control variate, docs/run.md)
      or "off" (without it, on the forcing control variate alone; the same expectation, larger
      error bars for the same work).
    seed: the random seed; threads: worker threads (0 = all cores); simd:
      "auto"|"scalar"|"sse2"|"avx2"|"avx512". The same parameters, band, precision and seed
      give bitwise the numbers of the command line, whatever threads and simd.
    progress: True draws a bar (tqdm: text in a terminal, a widget in a notebook); a
      callable gets progress(fraction, message) on this thread, about ten times a second.

    Returns a Result (numpy arrays omega [rad/s], C_x, stderr, theory [m^2 s], ...).
    Raises ValueError for bad parameters or requests, before any work. The run releases
    the GIL. Ctrl-C stops it at the next block of steps and raises KeyboardInterrupt with
    the partial Result (complete False) as `error.result`; resume(error.result) continues it.
    Warns ModelWarning where no theory holds (theory_kind none: eps beyond the measured
    limits of docs/model.md §7.4, stalling forces) and PrecisionWarning when the budget ran out before the precision.
    """
    if precision is not None and duration is not None:
        raise ValueError("precision excludes duration: a fixed duration sets the work, not a target")
    if realizations is not None and precision is not None:
        raise ValueError("precision excludes realizations: a fixed count sets the work, not a target")
    if duration is not None and not _real("duration", duration) > 0:
        raise ValueError(f"duration: need a positive number of seconds (got {duration!r})")
    if realizations is not None and _whole("realizations", realizations, _MOST_U64) == 0:
        raise ValueError("realizations: need at least 1 (leave it out to run to a precision)")
    if not isinstance(control_variate, str) or control_variate not in ("shadow", "off"):
        raise ValueError(f"control_variate: need 'shadow' or 'off' (got {control_variate!r})")
    p = _as_parameters(params)
    request = {"omega_min": _real("omega_min", omega_min), "omega_max": _real("omega_max", omega_max),
               "points_per_decade": _whole("points", points, _MOST_INT),
               "precision": _real("precision", _RUN["precision"] if precision is None else precision),
               "duration": float(duration or 0), "realizations": int(realizations or 0),
               "seed": _whole("seed", seed, _MOST_U64), "control_variate": control_variate == "shadow"}
    _whole("threads", threads, _MOST_INT)
    handle = _core.new_run(*p._args(), request)
    _warn_if_no_theory_holds(p)
    return _drive(handle, threads, simd, progress)


def resume(result, *, threads=0, simd="auto", progress=False):
    """Continues an interrupted run (a Result with complete False, e.g. the `result` of
    the KeyboardInterrupt that stopped run()) to its end: the Result is bitwise that of an
    unbroken run. threads, simd and progress as for run(); they change no number."""
    if not isinstance(result, Result) or result.state is None:
        raise ValueError("resume: expected the Result of an interrupted run (it holds the run's state)")
    return _drive(_core.load_run(result.state), threads, simd, progress)


# ---------------------------------------------------------------------------------------
# Reading the command line's outputs

# The landmarks PREFIX.json holds, in its order (a spring's last four only with drive="spring").
_LANDMARK_KEYS = ("renewal_rate", "omega_c", "diffusion_D", "eq1_prefactor", "coupling_eps", "forces_can_stall",
                  "omega_s", "omega_resonance", "d0", "C_x_zero")
_PARAMETER_KEY = _re.compile(r"^(%s)(_\d+)?$" % "|".join(_re.escape(k.removesuffix("_l"))
                                                        for k in _core.parameter_keys()))
# A key is one word; prose with " = " in it (the "# columns:" line) is not a KEY = VALUE line.
_KEY = _re.compile(r"^\w+\s*$")
_SUB_BAND = _re.compile(r"^sub_band (\d+): omega (\S+) \.\. (\S+), dt = (\S+) s, duration = (\S+) s, "
                        r"warm_up = (\S+) s at dt (\S+) s, shadow = (true|false), realizations = (\d+)")
# A run's TSV lines that repeat what PREFIX.json holds elsewhere: the realizations summed over
# the sub-bands, a spring's mean_speed (its v), and the columns derived from C_x (omega^2 C_x,
# M^2 omega^4 C_x) and from the parameters (Eq. (1), eq1()).
_RUN_TABLE_ONLY = ("realizations", "mean_speed")
_RUN_DERIVED_COLUMNS = ("C_v", "C_F", "C_eq1")
# A run's per-point estimator: the TSV's code, the JSON's word.
_ESTIMATORS = {0.0: "plain", 1.0: "forcing", 2.0: "shadow"}
# A run's per-point theory kind: the TSV's code, the JSON's word.
_THEORY_KINDS = {0.0: "none", 1.0: "first_order", 2.0: "second_order", 3.0: "quasi_static"}


def _number(text):
    """A value as PREFIX.json holds it: an int without '.', 'e' or 'E', else a float, true and
    false as bools, any other text as text."""
    try:
        value = float(text)
    except ValueError:
        return {"true": True, "false": False}.get(text, text)
    return int(text) if _re.fullmatch(r"[+-]?\d+", text) else value


def _read_table(text, path):
    """A TSV of the command line: '# key = value  # note' lines, a column line (plain,
    or '#'-prefixed), then tab-separated rows; a run's in the keys and types of its
    PREFIX.json."""
    data = {}
    parameters, landmarks, names, rows = {}, {}, None, []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        body = line[1:].strip() if line.startswith("#") else None
        if names is None and "\t" in line and (body if body is not None else line).split("\t")[0] == "omega":
            names = (body if body is not None else line).split("\t")
            continue
        if body is not None:
            if body.startswith("slidespec ") and "=" not in body:
                data["slidespec_version"] = body.split()[1]
            elif match := _SUB_BAND.match(body):
                b, low, high, dt, duration, warm_up, warm_up_dt, shadow, count = match.groups()
                data.setdefault("sub_bands", []).append(
                    {"omega_low": float(low), "omega_high": float(high), "dt": float(dt),
                     "duration": float(duration), "warm_up": float(warm_up), "warm_up_dt": float(warm_up_dt),
                     "shadow": shadow == "true", "realizations": int(count)})
            elif " = " in body and _KEY.match(body.split(" = ", 1)[0]):
                key, value = body.split(" = ", 1)
                value, _, note = value.partition("  #")
                key, value, note = key.strip(), value.strip(), note.strip()
                if _PARAMETER_KEY.match(key):
                    parameters[key] = _number(value)
                elif key in _LANDMARK_KEYS:  # doubles, as the JSON holds them ("0" is 0.0)
                    landmarks[key] = value == "true" if value in ("true", "false") else float(value)
                elif key == "measured_mean_speed":
                    error = _re.search(r"\+-\s*(\S+)", note)
                    data[key] = {"value": float(value),
                                 "standard_error": float(error.group(1)) if error else None}
                elif key == "seed":
                    data.setdefault("request", {})["seed"] = int(value)
                elif key == "control_variate":
                    data.setdefault("request", {})["control_variate"] = value
                elif key == "reached_precision":
                    data[key] = _number(value)
                    if target := _re.search(r"\(target (\S+)\)", note):
                        data.setdefault("request", {})["precision"] = float(target.group(1))
                elif key == "theory_kind":
                    data[key] = value
                    reason = note.partition("; ")[2]
                    if reason:
                        data["theory_kind_note"] = reason
                elif key == "stationary":
                    data[key] = _number(value)
                    if note:
                        data["stationarity"] = note
                else:
                    data[key] = _number(value)
            continue
        if names is None:
            raise ValueError(f"{path}: line {number}: a data row before the column line")
        fields = line.split("\t") if "\t" in line else line.split()
        if len(fields) != len(names):
            raise ValueError(f"{path}: line {number}: {len(fields)} fields, the column line has {len(names)}")
        try:
            rows.append({name: float(field) for name, field in zip(names, fields)})
        except ValueError:
            raise ValueError(f"{path}: line {number}: a field that is not a number") from None
    if names is None:
        raise ValueError(f"{path}: no column line (omega ...): not a slidespec table")
    if parameters:
        data["parameters"] = parameters
    if landmarks:
        if "forces_can_stall" not in landmarks:  # the TSV's header leaves it out
            landmarks["forces_can_stall"] = Parameters.from_dict(parameters, data.get("case", "reference")
                                                                 ).landmarks["forces_can_stall"]
        data["landmarks"] = {key: landmarks[key] for key in _LANDMARK_KEYS if key in landmarks}
    if "complete" in data:  # a run's table
        data.setdefault("label", data.get("case"))  # printed only when it differs from the case
        for key in _RUN_TABLE_ONLY:
            data.pop(key, None)
        rows = [{name: (_ESTIMATORS.get(value, value) if name == "estimator" else
                        _THEORY_KINDS.get(value, value) if name == "theory_kind" else
                        value if _math.isfinite(value) else None)
                 for name, value in row.items() if name not in _RUN_DERIVED_COLUMNS} for row in rows]
    data["points"] = rows
    return data


_MOST_TABLE_BYTES = 1 << 30


_SWEEP_RUN = _re.compile(r"^# run_\d+ = .*  # (.+)$")


def _sweep_runs(text, path):
    """The files of a sweep's runs, beside the sweep's own table; None for any other file."""
    directory = _os.path.dirname(_os.fspath(path))
    if text.startswith("# slidespec ") and " sweep: " in text.split("\n", 1)[0]:
        return [_os.path.join(directory, m.group(1)) for line in text.splitlines()
                if (m := _SWEEP_RUN.match(line))]
    if text.lstrip().startswith("{"):
        try:
            data = _json.loads(text)
        except _json.JSONDecodeError:
            return None
        if isinstance(data, dict) and "runs" in data and "points" not in data:
            return [_os.path.join(directory, run["table"]) for run in data["runs"]]
    return None


def read(path):
    """Reads an output of the command line (`slidespec run`, `theory`, `analyze`, `merge`)
    as a Result (an Analysis for analyze's output); a `sweep`'s combined table as a list of
    Results, one per run, read from the runs' own files it names.

    path: PREFIX.tsv or PREFIX.json (both to every bit: each number is printed in the
    shortest form that reads back as the same double). The TSV's column line may be plain
    or start with '#'. Columns keep the file's
    units: omega [rad/s]; C_x, stderr, theory [m^2 s]. Raises OSError when the
    file cannot be read (a directory, a device, a pipe, or over 1 GiB: a table is a few
    kB) and ValueError when it is not a slidespec table."""
    with open(path, "rb", buffering=0) as f:
        info = _os.fstat(f.fileno())
        if not _stat.S_ISREG(info.st_mode):
            raise OSError(_errno.EINVAL, "not a regular file (a slidespec table is a file)", str(path))
        if info.st_size > _MOST_TABLE_BYTES:
            raise OSError(_errno.EFBIG, f"{info.st_size} bytes, more than a slidespec table's "
                          f"{_MOST_TABLE_BYTES}", str(path))
        raw = f.read(_MOST_TABLE_BYTES + 1)
    if len(raw) > _MOST_TABLE_BYTES:
        raise OSError(_errno.EFBIG, f"more than a slidespec table's {_MOST_TABLE_BYTES} bytes", str(path))
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text ({e.reason} at byte {e.start}): not a slidespec table") from None
    if runs := _sweep_runs(text, path):
        return [read(run) for run in runs]
    if text.lstrip().startswith("{"):
        try:
            data = _json.loads(text)
        except _json.JSONDecodeError as e:
            raise ValueError(f"{path}: not valid JSON ({e})") from None
        if not isinstance(data, dict) or "points" not in data:
            raise ValueError(f"{path}: not a slidespec result (no points)")
    else:
        data = _read_table(text, path)
    if "record" in data or "usable_band" in data:
        return Analysis(data)
    return Result(data)


# ---------------------------------------------------------------------------------------
# Measured records

class Analysis(_Table):
    """The spectrum of a measured (or synthetic) record, as `slidespec analyze` gives it.

    Columns (numpy arrays): omega [rad/s]; C_x [m^2 s] estimate; stderr [m^2 s] from the
    scatter between segments; floor [m^2 s] the sensor's q^2/12 + sigma^2 seen through the
    estimator; below_floor (bool) indistinguishable from sensor noise; n_avg; bandwidth
    [rad/s]; dof degrees of freedom; segment_samples; leaky (bool) window leakage may bias
    the point; C_low, C_high [m^2 s] the error bar (a 95.4% interval); theory [m^2 s] the
    compared model (at the fitted alpha) when asked. Field estimator {name, reason,
    segment_samples, segments, ...} says how the spectrum was estimated.
    Fields: slope_fit {slope, standard_error, chi2_per_dof, force_slope, omega_low,
    omega_high [rad/s], ...}; alpha_fit {alpha, standard_error, chi2_per_dof, ...};
    mean_speed [m/s]; usable_band {omega_low, omega_high} [rad/s] (with empty: true, both 0,
    where the sensor floor covers everything); dt, duration [s].
    """

    @property
    def slope(self):
        """The fitted exponent n of C_x ~ omega^-n... as a signed slope (-4 for omega^-4), or None."""
        fit = self._data.get("slope_fit")
        return fit["slope"] if fit else None

    @property
    def alpha(self):
        """The fitted alpha [-], or None."""
        fit = self._data.get("alpha_fit")
        return fit["alpha"] if fit else None

    @property
    def mean_speed(self):
        """The fitted mean sliding speed v [m/s]."""
        return _value(self._data.get("measured_mean_speed"))

    def __repr__(self):
        extra = "".join([f", slope {self.slope:.3f}" if self.slope is not None else "",
                         f", alpha {self.alpha:.3f}" if self.alpha is not None else ""])
        return f"<slidespec.Analysis: {len(self)} points{extra}>"


def analyze(t, x=None, *, dt=None, units="m", force=None, force_units=None, normal_stress=None,
            normal_stress_units="MPa", contact_area=0.0, normal_force=0.0, machine_stiffness=0.0,
            observable="auto", resolution=0.0, sensor_noise=0.0, omega_min=0.0, omega_max=0.0, points=8,
            fit_slope=None, compare=None, fit=None, fit_band=None, theory_order=2, time_tolerance=0.01,
            estimator="auto", window=None, resample="auto"):
    """Spectrum, slope and model fit of a sliding-distance record: `slidespec analyze`.

    t: sample times [s] (uniform within time_tolerance), or None with dt [s].
    x: positions in `units` ("m", "mm", "um", ...); v t is fitted and removed. None for a
      record of a force alone.
    force: the force channel (numpy array) in force_units "N", "kN", "MPa", "kPa" or "mu";
      a stress times contact_area [m^2], mu times normal_force [N] or times normal_stress
      (an array in normal_stress_units "MPa" or "kPa") and contact_area.
    machine_stiffness: K [N/m]: the observable is the slip x - F/K, and a compared case is
      driven through a spring k_drive = K. observable: "auto" (slip with K, force with a
      force, else displacement), "displacement", "force" (C_F [N^2 s]) or "slip".
    resolution: the sensor's quantization step q [m]; sensor_noise: its rms noise [m];
      together the white floor q^2/12 + sigma^2 (given: held in fits; else fitted).
    omega_min, omega_max: band [rad/s] (0 = what the record allows); points per decade.
    fit_slope: (low, high) [rad/s]: fit C_x ~ omega^slope there.
    compare: Parameters (or a case name) whose theory to set beside the data, on the
      record's terms: its v the measured mean speed and, with machine_stiffness, a spring
      drive (keys the Parameters set are kept).
    fit: "alpha" (the compared case's alpha), "power-law" (A (omega/pivot)^s + floor), or
      model parameters fitted jointly with the floor, "alpha,a" or ["alpha", "a"] (any of
      alpha, a, k_drive); over fit_band (low, high) [rad/s] (default: every point for
      "power-law", the usable band for a model fit, for "alpha" the usable band within
      5 v/a .. omega_c/3).
    estimator: "auto" (Welch up to 1e7 samples, streaming beyond), "welch" (Hann, 50% overlap,
      8 segments of first differences: 9 x 2 pi / T to Nyquist) or "streaming" (the run's).
    window: (t0, t1) [s] in record time: only those samples (default: the longest sliding
      segment when velocity steps or holds split the record, or the strokes' middles of a
      reciprocating record; the result's segments, each with its kind -- sliding, hold,
      loading, step, reversal --, strokes and notes say which). resample: "auto" (jitter interpolated linearly onto the median interval, a
      gap refused), "off", "median" or an interval [s] (gaps and rate changes interpolated);
      the band is cut where interpolation filters it.
    theory_order: 2 (default) compares and fits with the second-order theory where it
      can be computed (one touching level, a constant force), else the first; 1 the
      first order always. The result's theory_order field says which was used; whether
      either holds is the parameters' theory_kind (docs/model.md §7.4).
    Returns an Analysis (ok False when a fit does not describe the data; each fit's ok and
    failure say why, and a ModelWarning repeats it; without a fit ok is True, as in the
    command's JSON, even with no usable band). Warns RecordWarning where the command line
    warns: no usable band (resolution or sensor_noise in the wrong unit, both in metres, when
    the floor lies above the spectrum everywhere), a mean speed implausible for friction (x
    in the wrong units), points biased by the window's leakage, a spectrum below the floor
    (the sensor finer than resolution says, or a quantization floor that is not white). Raises ValueError for a
    malformed record or request.
    """
    if x is None and force is None:
        raise ValueError("x: no positions given; give x [units], or force= (with force_units=) for a record "
                         "of a force alone")
    names = None
    if fit is not None and fit not in ("alpha", "power-law"):
        names = _core.parse_fit_parameters(",".join(fit) if isinstance(fit, (list, tuple)) else str(fit))
        fit = ",".join(names)
    if fit not in (None, "power-law") and compare is None:
        raise ValueError(f"fit={fit!r} needs compare=Parameters(...)")
    if fit == "power-law" and fit_slope is not None:
        raise ValueError("fit='power-law' and fit_slope both fit a power law; give one (fit_band sets the band)")
    for name, value in (("units", units), ("estimator", estimator)):
        if not isinstance(value, str):
            raise TypeError(f"{name}: expected a word (str), got {type(value).__name__} {value!r}")
    dt = 0.0 if dt is None else _real("dt", dt)
    time_tolerance = _real("time_tolerance", time_tolerance)
    omega_min, omega_max = _real("omega_min", omega_min), _real("omega_max", omega_max)
    resolution, sensor_noise = _real("resolution", resolution), _real("sensor_noise", sensor_noise)
    points = _whole("points", points, _MOST_INT)
    theory_order = _whole("theory_order", theory_order, 2)
    if not isinstance(resample, str):
        resample = _real("resample", resample)
    if window is not None:
        # The command line's "T0:T1" is a pair here; a string would be read letter by letter.
        if isinstance(window, (str, bytes)) or _np.ndim(window) != 1 or len(window) != 2:
            raise TypeError(f"window: expected a pair (t0, t1) [s], got {type(window).__name__} {window!r}")
        window = (_real("window t0", window[0]), _real("window t1", window[1]))
    time = _np.empty(0) if t is None else _np.asarray(t, dtype=float).ravel()
    samples = _np.empty(0) if x is None else _np.asarray(x, dtype=float).ravel()
    channel = None if force is None else _np.asarray(force, dtype=float).ravel()
    normal = None if normal_stress is None else _np.asarray(normal_stress, dtype=float).ravel()
    record = {"dt": float(dt or 0), "units": str(units), "time_tolerance": float(time_tolerance),
              "window": None if window is None else (float(window[0]), float(window[1])),
              "resample": resample if isinstance(resample, str) else "interval",
              "resample_interval": 0.0 if isinstance(resample, str) else float(resample),
              "force": channel, "force_units": force_units, "normal_stress": normal,
              "normal_stress_units": str(normal_stress_units), "contact_area": float(contact_area),
              "normal_force": float(normal_force), "machine_stiffness": float(machine_stiffness),
              "observable": str(observable)}
    request = {"omega_min": float(omega_min), "omega_max": float(omega_max), "points_per_decade": int(points),
               "resolution": float(resolution), "sensor_noise": float(sensor_noise), "estimator": str(estimator)}
    spectrum = _core.Spectrum(time, samples, record, request)
    data = spectrum.to_dict()
    usable = (data["usable_band"]["omega_low"], data["usable_band"]["omega_high"])
    band = usable if fit_band is None else (float(fit_band[0]), float(fit_band[1]))
    fits = []
    if fit_slope is not None:
        data["slope_fit"] = spectrum.fit_slope(float(fit_slope[0]), float(fit_slope[1]))
        fits.append(data["slope_fit"])
    if fit == "power-law":
        every = (data["points"][0]["omega"], data["points"][-1]["omega"])
        data["power_law_fit"] = spectrum.fit_power_law(*(every if fit_band is None else band))
        fits.append(data["power_law_fit"])
    if compare is not None:
        p = _as_parameters(compare)
        p = _rebuild_parameters(p.case, spectrum.record_terms(*p._args()))
        if fit == "alpha":
            if fit_band is None:
                band = spectrum.default_alpha_band(*p._args())
            data["alpha_fit"] = spectrum.fit_alpha(*p._args(), float(band[0]), float(band[1]), int(theory_order))
            fits.append(data["alpha_fit"])
            p = p.replace(alpha=data["alpha_fit"]["alpha"])
        elif names:
            data["model_fit"] = spectrum.fit_model(*p._args(), names, float(band[0]), float(band[1]),
                                                   int(theory_order))
            fits.append(data["model_fit"])
            p = p.replace(**{name: data["model_fit"]["parameters"][name]["value"] for name in names})
        data["compare_case"] = p.case
        data["model_parameters"] = p.to_dict()
        data["theory_order"] = spectrum.model_order(*p._args(), int(theory_order))
        for point, value in zip(data["points"], spectrum.model(*p._args(), int(theory_order))):
            point["theory"] = float(value)
    for result in fits:
        for point, value, residual in zip(data["points"], result.pop("fit", []), result.pop("residual", [])):
            point["fit"], point["residual"] = float(value), float(residual)
    data["ok"] = data["spectrum_ok"] and all(result["ok"] for result in fits)
    _warn_as_analyze_does(data, units)
    return Analysis(data)


# The command line's thresholds (include/slidespec/analysis.hpp): below this share of the white
# floor at the top of the band the floor line misleads; above this speed [m/s] the unit is the
# likely cause.
_WHITE_FLOOR_SHORTFALL = _core.white_floor_shortfall
_IMPLAUSIBLE_SPEED = _core.implausible_speed


def _warn_as_analyze_does(data, units):
    """The warnings and failed fits `slidespec analyze` prints, read from the result's fields."""
    def warn(text, kind=RecordWarning):
        _warnings.warn(text, kind, stacklevel=4)

    speed = _value(data.get("measured_mean_speed"))
    if data["observable"]["name"] != "force" and speed is not None and abs(speed) > _IMPLAUSIBLE_SPEED:
        warn(f"mean speed {speed:.6g} m/s is implausible for friction; likely cause: x read in units={units!r}; "
             "give units='mm', 'um', ...")
    band = data["usable_band"]
    if not band["omega_high"] > band["omega_low"] and band["floor_above_spectrum"]:
        warn("no usable band: the sensor floor lies above the spectrum everywhere; likely cause: resolution or "
             f"sensor_noise in the wrong unit (both in metres whatever units={units!r}: 0.5 um is 0.5e-6)")
    elif not band["omega_high"] > band["omega_low"]:
        lowest = data["points"][0]
        warn("no usable band: at the lowest point, where the band starts, the spectrum does not clear the sensor "
             f"floor by the factor the usable band needs (the floor at most 10% of {data['observable']['spectrum']}; "
             f"it is {100 * lowest['floor'] / lowest[data['observable']['spectrum']]:.3g}% there)")
    if leaky := data["estimator"].get("leaky_points", 0):
        warn(f"{leaky} points may be biased high by the window's leakage (the spectrum is steeper than a "
             "prewhitened Hann window allows there; column leaky)")
    if 0 < data["top_to_floor"] < _WHITE_FLOOR_SHORTFALL:
        top = f"the highest point lies at {data['top_to_floor']:.6g}"
        if data["readings_off_grid"]:
            warn(f"{top} of the white floor: the record's steps are not whole multiples of the resolution given, "
                 "its sensor reads finer, so the floor line lies too high")
        elif data["quantization_variance"] == 0:
            warn(f"{top} of the white sigma^2 floor: the record holds less noise there than the sensor_noise given, "
                 "so the floor line lies too high")
        else:
            warn(f"{top} of the white q^2/12 floor: the quantization error is not white (a steady ramp read "
                 "without noise to dither it; docs/analysis.md), so the floor line is only a guide")
    if data.get("slope_fit", {}).get("reaches_floor"):
        warn("the slope band reaches beyond the usable band, where the sensor floor bends the spectrum")
    for name, key in (("slope", "slope_fit"), ("alpha", "alpha_fit"), ("power-law", "power_law_fit"),
                      ("model", "model_fit")):
        if key in data and not data[key]["ok"]:
            warn(f"{name} fit FAILED: {data[key]['failure']}", ModelWarning)
    if not data.get("spectrum_ok", True):
        warn(f"not a spectrum (ok False): {data['spectrum_failure']}", ModelWarning)


def synth(params="reference", *, sample_interval=_SENSOR["sample_interval"], duration=_SENSOR["duration"],
          resolution=_SENSOR["resolution"], sensor_noise=_SENSOR["sensor_noise"], seed=_SENSOR["seed"]):
    """A synthetic displacement-sensor record of the simulated slider: `slidespec synth`.

    sample_interval [s], duration [s]; resolution: quantization step q [m] (0 = exact);
    sensor_noise: rms white noise before quantization [m]; seed. Returns (t, x): times [s]
    and positions x = v t + xi [m], numpy arrays."""
    p = _as_parameters(params)
    sensor = {"sample_interval": _real("sample_interval", sample_interval), "duration": _real("duration", duration),
              "resolution": _real("resolution", resolution), "sensor_noise": _real("sensor_noise", sensor_noise),
              "seed": _whole("seed", seed, _MOST_U64)}
    step, start, x = _core.synthesize(*p._args(), sensor)
    return start + step * _np.arange(x.size), x
