"""The theory of a parameter set: C_x, the spring force, Eq. (1), the long-time motion."""

import numpy as _np

from . import _core
from ._checks import _MOST_INT, _real, _whole
from ._parameters import _RUN, _as_parameters


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
