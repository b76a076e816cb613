"""The drives figure (`slidespec paper drives`, docs/model.md §9): a constant force against
springs of several stiffnesses, and a case a constant force would stall, driven through a
spring. plot_spectra.py hands its tables here with `--layout drives`.

Three panels: (a) C_x of every sliding case, simulation with error bars beside the exact
theory, omega_s (dashed) and the resonance sqrt((N k0 + k_drive)/M) (dotted) marked per
spring; (b) the force each drive's sensor sees: the spring's k_drive^2 C_x, and for the
constant force the block's inertial force M^2 omega^4 C_x; (c) the stall case under a
spring, with the first-order theory drawn dashed where it is not expected to hold.
"""

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

import plot_spectra as ps


def _is_spring(spectrum):
    return spectrum.metadata.get("drive") == "spring"


def _stalls(spectrum):
    """Whether a constant force could stall this block: alpha F_kin >= 2 (F_drive - F_kin)."""
    alpha, f_drive, f_kin = (spectrum.number(key) for key in ("alpha", "F_drive", "F_kin"))
    return None not in (alpha, f_drive, f_kin) and alpha * f_kin >= 2 * (f_drive - f_kin)


def _label(spectrum):
    if not _is_spring(spectrum):
        return "constant force"
    return f"spring, $k_{{drive}}$ = {ps._short_number(spectrum.metadata.get('k_drive', '?'))} N/m"


def _force_factor(spectrum, omega):
    """The drive's force spectrum per C_x: k_drive^2 for a spring, M^2 omega^4 (the block's
    inertial force) for a constant force."""
    if _is_spring(spectrum):
        return np.full_like(omega, spectrum.number("k_drive") ** 2)
    return spectrum.number("M") ** 2 * omega ** 4


def _draw(axes, spectrum, fine, color, factor_of, theory_style="-"):
    omega = spectrum.columns["omega"]
    values = spectrum.columns["C_x"] * factor_of(spectrum, omega)
    stderr = spectrum.columns["stderr"] * factor_of(spectrum, omega)
    x, y, keep = ps._log_positive(omega, values)
    if fine is None and "theory" in spectrum.columns:
        fine = (omega, spectrum.columns["theory"])
    if fine is not None:
        fine_omega, fine_c = fine
        inside = (fine_omega >= omega.min() / 1.0001) & (fine_omega <= omega.max() * 1.0001)
        tx, ty, _ = ps._log_positive(fine_omega[inside], fine_c[inside] * factor_of(spectrum, fine_omega[inside]))
        axes.plot(tx, ty, theory_style, color=color, linewidth=1.3, zorder=2, gid=ps.THEORY_ID)
    markers = axes.errorbar(x, y, yerr=ps._log_error_bars(values[keep], stderr[keep]), fmt="o", markersize=3.5,
                            color=color, markeredgecolor="black", markeredgewidth=0.4, ecolor=color,
                            elinewidth=1.0, capsize=2, zorder=3)
    markers[0].set_gid(ps.SIMULATION_ID)


def _mark_landmarks(axes, spectrum, color):
    omega_s, resonance = spectrum.number("omega_s"), spectrum.number("omega_resonance")
    if omega_s:
        axes.axvline(math.log10(omega_s), linestyle="--", color=color, linewidth=1.0, zorder=0)
    if resonance:
        axes.axvline(math.log10(resonance), linestyle=":", color=color, linewidth=1.0, zorder=0)


def _style(axes, ylabel, title):
    axes.set_ylabel(ylabel, fontsize=11)
    axes.set_xlabel(r"$\log_{10}\,\omega$ (rad/s)", fontsize=11)
    axes.grid(True, color="0.9", linewidth=0.6)
    axes.tick_params(labelsize=9)
    axes.set_title(title, fontsize=10.5, loc="left")


def render(spectra, labels, args, fine_theories=None):
    del labels  # the drives are named from their tables' metadata
    fine_theories = fine_theories or [None] * len(spectra)
    if any(not s.simulated for s in spectra):
        raise ps.InputError("the drives figure draws run tables only")
    sliding = [i for i, s in enumerate(spectra) if not (_is_spring(s) and _stalls(s))]
    stalled = [i for i, s in enumerate(spectra) if _is_spring(s) and _stalls(s)]
    if not sliding:
        raise ps.InputError("the drives figure needs at least one sliding case")
    size = args.size or (13, 4.6)
    figure, panels = plt.subplots(1, 3 if stalled else 2, figsize=size, dpi=args.dpi, layout="constrained")
    colors = args.colors or [f"C{i % 10}" for i in range(len(spectra))]
    colors = [colors[i % len(colors)] for i in range(len(spectra))]

    cx, cf = panels[0], panels[1]
    handles, texts = [], []
    for i in sliding:
        s = spectra[i]
        _draw(cx, s, fine_theories[i], colors[i], lambda _s, w: np.ones_like(w))
        _draw(cf, s, fine_theories[i], colors[i], _force_factor, "-" if _is_spring(s) else "-.")
        if _is_spring(s):
            _mark_landmarks(cx, s, colors[i])
            _mark_landmarks(cf, s, colors[i])
        handles.append(Line2D([], [], marker="o", color=colors[i], markeredgecolor="black", markeredgewidth=0.4))
        texts.append(_label(s))
    handles += [Line2D([], [], marker="o", linestyle="none", color="0.35", markeredgecolor="black",
                       markeredgewidth=0.4),
                Line2D([], [], color="0.35", linewidth=1.3),
                Line2D([], [], color="0.35", linestyle="--", linewidth=1.0),
                Line2D([], [], color="0.35", linestyle=":", linewidth=1.0)]
    texts += ["simulation, ±1 stderr", "exact first-order theory", r"$\omega_s = k_{drive} v/(F_{drive}-F_{kin})$",
              r"resonance $\sqrt{(N k_0 + k_{drive})/M}$"]
    cx.legend(handles, texts, fontsize=7.5, loc="lower left", framealpha=0.85, edgecolor="none")
    _style(cx, r"$\log_{10}\,C_x$ (m² s)", "(a) the block's displacement")
    _style(cf, r"$\log_{10}\,C_F$ (N² s)", "(b) the drive's force")
    cf.text(0.02, 0.03, "spring: $k_{drive}^2 C_x$ (solid)\nconstant force: block's inertial\n"
            "force $M^2\\omega^4 C_x$ (dash-dot)", transform=cf.transAxes, fontsize=7.5, color="0.25",
            va="bottom")
    if stalled:
        st = panels[2]
        for i in stalled:
            s = spectra[i]
            _draw(st, s, fine_theories[i], colors[i], lambda _s, w: np.ones_like(w), "--")
            _mark_landmarks(st, s, colors[i])
        s = spectra[stalled[0]]
        speed = s.number("measured_mean_speed")
        note = (f"N = {ps._short_number(s.metadata.get('N', '?'))}, "
                f"$F_{{drive}}$ = {ps._short_number(s.metadata.get('F_drive', '?'))} N, "
                f"$F_{{kin}}$ = {ps._short_number(s.metadata.get('F_kin', '?'))} N, "
                f"$k_{{drive}}$ = {ps._short_number(s.metadata.get('k_drive', '?'))} N/m:\n"
                "a constant force would stall the block;\nthe spring keeps it sliding at v, intermittently.\n"
                "dashed: the first-order theory,\nnot expected to hold here")
        st.text(0.03, 0.03, note, transform=st.transAxes, fontsize=7.5, color="0.25", va="bottom")
        if speed:
            st.text(0.97, 0.97, f"stationary: {s.metadata.get('stationary', '?')}, mean speed "
                    f"{speed / s.number('v'):.4f} v", transform=st.transAxes, fontsize=7.5, color="0.25",
                    ha="right", va="top")
        _style(st, r"$\log_{10}\,C_x$ (m² s)", "(c) a stall case under a spring")
    if args.title:
        figure.suptitle(args.title, fontsize=12)
    return figure
