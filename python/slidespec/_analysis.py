"""Measured records: their analysis, and synthetic ones."""

import os as _os
import warnings as _warnings

import numpy as _np

from . import _core
from ._checks import _MOST_INT, _MOST_U64, _pair, _real, _samples, _whole
from ._kinds import ModelWarning, RecordWarning
from ._parameters import _SENSOR, _as_parameters
from ._results import _Table, _value


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
            normal_stress_units="MPa", contact_area=0.0, normal_force=0.0, machine_stiffness=None,
            observable="auto", resolution=0.0, sensor_noise=0.0, omega_min=0.0, omega_max=0.0, points=8,
            fit_slope=None, compare=None, fit=None, fit_band=None, theory_order=2, time_tolerance=0.01,
            estimator="auto", window=None, resample="auto", friction_force=0.0, slider_mass=0.0):
    """Spectrum, slope and model fit of a sliding-distance record: `slidespec analyze`.

    t: sample times [s] (uniform within time_tolerance), or None with dt [s].
    x: positions in `units` ("m", "mm", "um", ...); v t is fitted and removed. None for a
      record of a force alone.
    force: the force channel (numpy array) in force_units "N", "kN", "MPa", "kPa" or "mu";
      a stress times contact_area [m^2], mu times normal_force [N] or times normal_stress
      (an array, or one number, in normal_stress_units "MPa" or "kPa") and contact_area.
    machine_stiffness: K [N/m] > 0 (None: no machine): the observable is the slip x - F/K, and a compared case is
      driven through a spring k_drive = K. observable: "auto" (slip with K, force with a
      force, else displacement), "displacement", "force" (C_F [N^2 s]) or "slip".
    resolution: the sensor's quantization step q [m]; sensor_noise: its rms noise [m];
      together the white floor q^2/12 + sigma^2 (given: held in fits; else fitted).
    omega_min, omega_max: band [rad/s] (0 = what the record allows); points per decade.
    fit_slope: (low, high) [rad/s]: fit C_x ~ omega^slope there.
    compare: Parameters (or a case name) whose theory to set beside the data, on the
      record's terms: its v the measured mean speed and, with machine_stiffness, a spring
      drive (keys the Parameters set are kept). compare="rig": the case built from the
      record and the rig (machine_stiffness, the mean friction or friction_force [N], dF/dv
      across a velocity step, slider_mass [kg] if known; docs/analysis.md "The model on a
      rig's scale").
    fit: "alpha" (the compared case's alpha), "power-law" (A (omega/pivot)^s + floor), or
      model parameters fitted jointly with the floor, "alpha,a" or ["alpha", "a"] (any of
      alpha, a, k_drive, k0); over fit_band (low, high) [rad/s] (default: every point for
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
    if isinstance(t, (str, bytes, _os.PathLike)):
        raise TypeError(f"t: expected the sample times [s] (an array) or None, got the path {t!r}; analyze takes "
                        "arrays: load the record first (numpy.loadtxt), or run `slidespec analyze FILE`")
    if x is None and force is None:
        shape = _np.shape(t) if t is not None else None
        given = f" (the one array given is t, the sample times, of shape {shape})" if shape else ""
        raise ValueError("x: no positions given" + given + "; give analyze(t, x) with x [units] a 1-D array, "
                         "or force= (with force_units=) for a record of a force alone")
    options = {name: value for name, value in locals().items() if name not in ("t", "x")}
    record, plan = _format_and_plan(**options)
    if t is None and not record["dt"] > 0:
        raise ValueError(f"dt: {record['dt']} s; without the sample times t, give the sampling interval dt > 0 [s]")
    time = _np.empty(0) if t is None else _samples("t", t)
    samples = _np.empty(0) if x is None else _samples("x", x)
    return _analysis(*_core.analyze(time, samples, record, plan), stacklevel=3)


def _analysis(data, columns, messages, stacklevel, about=""):
    """The binding's (fields, columns, warnings) as an Analysis, each warning given at the
    caller's `stacklevel` (prefixed by `about`, the file it is of among many)."""
    for kind, _, text in messages:
        if kind == "warning":
            _warnings.warn(about + text, RecordWarning, stacklevel=stacklevel)
        elif kind == "failed_fit":
            _warnings.warn(about + text, ModelWarning, stacklevel=stacklevel)
        else:
            _warnings.warn(f"{about}not a spectrum (ok False): {text}", ModelWarning, stacklevel=stacklevel)
    return Analysis(data, columns=columns)


def _format_and_plan(*, dt, units, force, force_units, normal_stress, normal_stress_units, contact_area, normal_force,
                     machine_stiffness, observable, resolution, sensor_noise, omega_min, omega_max, points, fit_slope,
                     compare, fit, fit_band, theory_order, time_tolerance, estimator, window, resample,
                     friction_force, slider_mass):
    """analyze's keywords, checked, as the binding's (format, plan) dicts; units None: each
    file's header says."""
    if isinstance(fit, (list, tuple)):
        fit = ",".join(str(name) for name in fit)
    for name, value in (("units", "m" if units is None else units), ("estimator", estimator)):
        if not isinstance(value, str):
            raise TypeError(f"{name}: expected a word (str), got {type(value).__name__} {value!r}")
    dt = 0.0 if dt is None else _real("dt", dt)
    if machine_stiffness is not None and not _real("machine_stiffness", machine_stiffness) > 0:
        raise ValueError(f"machine_stiffness: {machine_stiffness} N/m; a stiffness K > 0 gives the slip x - F/K "
                         "(None: no slip)")
    fit_slope = None if fit_slope is None else _pair("fit_slope", fit_slope)
    fit_band = None if fit_band is None else _pair("fit_band", fit_band)
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
    channel = None if force is None else _samples("force", force)
    constant_stress = normal_stress is not None and _np.ndim(normal_stress) == 0
    normal = None if normal_stress is None or constant_stress else _samples("normal_stress", normal_stress)
    record = {"dt": float(dt or 0), "units": None if units is None else str(units),
              "time_tolerance": float(time_tolerance),
              "window": None if window is None else (float(window[0]), float(window[1])),
              "resample": resample if isinstance(resample, str) else "interval",
              "resample_interval": 0.0 if isinstance(resample, str) else float(resample),
              "force": channel, "force_units": force_units, "normal_stress": normal,
              "normal_stress_units": str(normal_stress_units), "contact_area": float(contact_area),
              "normal_force": float(normal_force), "machine_stiffness": float(machine_stiffness or 0),
              "normal_stress_value": _real("normal_stress", normal_stress) if constant_stress else 0.0,
              "observable": str(observable)}
    rig = isinstance(compare, str) and compare == "rig"
    compared = None if compare is None or rig else _as_parameters(compare)
    plan = {"omega_min": float(omega_min), "omega_max": float(omega_max), "points_per_decade": int(points),
            "resolution": float(resolution), "sensor_noise": float(sensor_noise), "estimator": str(estimator),
            "fit_slope": None if fit_slope is None else (float(fit_slope[0]), float(fit_slope[1])),
            "compare_case": "rig" if rig else "" if compared is None else compared.case,
            "friction_force": _real("friction_force", friction_force),
            "slider_mass": _real("slider_mass", slider_mass),
            "overrides": [] if compared is None else compared._args()[1],
            "fit": "" if fit is None else str(fit),
            "fit_band": None if fit_band is None else (float(fit_band[0]), float(fit_band[1])),
            "theory_order": int(theory_order)}
    return record, plan


def synth(params="reference", *, sample_interval=_SENSOR["sample_interval"], duration=None,
          resolution=_SENSOR["resolution"], sensor_noise=_SENSOR["sensor_noise"], seed=_SENSOR["seed"],
          program=None, strokes=None, stroke_length=None, dwell=None, load_point=False):
    """A synthetic displacement-sensor record of the simulated slider: `slidespec synth`.

    sample_interval [s], duration [s] (default 1000); resolution: quantization step q [m]
    (0 = exact); sensor_noise: rms white noise before quantization [m]; seed. The drive
    (docs/analysis.md, "Drive programs"), either of: program=[(F, T), ...], the load point at
    F x the case's v for T seconds (F = 0 a hold, negative backwards); strokes=K with
    stroke_length=L [m] and dwell=T [s], a reciprocating record. Either sets the record's
    length (no duration). load_point=True (drive=spring): what a rig records, x the load
    point's position and the spring's force. Returns (t, x), or (t, x, F) with load_point:
    times [s], positions [m] (x = the load point's path + xi, or the load point's), F [N],
    numpy arrays."""
    p = _as_parameters(params)
    if program is not None and strokes is not None:
        raise ValueError("program: not with strokes; give one drive")
    drive = "program" if program is not None else "strokes" if strokes is not None else None
    if drive and duration is not None:
        raise ValueError(f"{drive}: sets the record's length; not with duration")
    for name, given in (("stroke_length", stroke_length), ("dwell", dwell)):
        if given is not None and strokes is None:
            raise ValueError(f"{name}: only with strokes")
    if strokes is not None and stroke_length is None:
        raise ValueError("strokes: needs stroke_length, a stroke's length in m")
    stretches = []
    for stretch in program or []:
        if len(stretch) != 2:
            raise ValueError(f"program: each stretch is (F, T), got {stretch!r}")
        stretches.append((_real("program speed factor", stretch[0]), _real("program duration", stretch[1])))
    if program is not None and not stretches:
        raise ValueError("program: no stretch; give [(F, T), ...]")
    sensor = {"sample_interval": _real("sample_interval", sample_interval),
              "duration": _real("duration", _SENSOR["duration"] if duration is None else duration),
              "resolution": _real("resolution", resolution), "sensor_noise": _real("sensor_noise", sensor_noise),
              "seed": _whole("seed", seed, _MOST_U64), "program": stretches,
              "strokes": None if strokes is None else float(_whole("strokes", strokes, _MOST_INT)),
              "stroke_length": 0.0 if stroke_length is None else _real("stroke_length", stroke_length),
              "dwell": 0.0 if dwell is None else _real("dwell", dwell), "load_point": bool(load_point)}
    step, start, x, force = _core.synthesize(*p._args(), sensor)
    t = start + step * _np.arange(x.size)
    return (t, x, force) if load_point else (t, x)
