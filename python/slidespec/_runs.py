"""Spectrum runs on their own thread, and their resumption."""

import atexit as _atexit
import math as _math
import threading as _threading
import time as _time
import warnings as _warnings

from . import _core
from ._checks import _MOST_INT, _MOST_U64, _real, _whole
from ._kinds import ModelWarning, PrecisionWarning
from ._parameters import _RUN, _as_parameters
from ._results import Result


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
    data, columns = handle.result()
    result = Result(data, None if data.get("complete") else handle.save(), columns)
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
        result = _finish(handle)
        if not result.complete:
            # Stopped from elsewhere (the interpreter's exit, a signal to the process): a
            # caller that does not look at `complete` would take a part for the whole.
            _warnings.warn("the run was stopped before it finished: its Result is partial (complete = False); "
                           "resume(result) continues it", RuntimeWarning, stacklevel=3)
        return result
    finally:
        with _driven_lock:
            _driven.discard(handle)


def _warn_if_no_theory_holds(p):
    marks = p.landmarks
    if marks["theory_kind"] == "none":
        _warnings.warn(f"no theory holds here (theory_kind = none): {marks['theory_kind_note']}", ModelWarning,
                      stacklevel=3)


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
