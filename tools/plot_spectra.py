#!/usr/bin/env python3
"""Plot slidespec spectrum tables (theory or simulated) as log10 C against log10 omega.

Usage: plot_spectra.py FILE [FILE ...] -o OUT.{png,pdf,svg} [--title T] [--labels A,B,...]
       [--theory T1,T2,...] [--colors C1,C2,...] [--size WxH] [--dpi D] [--no-residuals]
       [--omega-min W] [--omega-max W] [--no-eq1] [--kind displacement|velocity|force]

See docs/plots.md. Exit status 2, one line on stderr and no output file when an input
cannot be used.
"""

import argparse
import dataclasses
import math
import os
import re
import sys
import tempfile
import unicodedata

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # slidespec_tsv, beside this file
import slidespec_tsv  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
# Every computed point is written (PDF/SVG too): no merging of nearly collinear vertices.
matplotlib.rcParams["path.simplify"] = False
import matplotlib.pyplot as plt  # noqa: E402  (must follow the backend choice)
import numpy as np  # noqa: E402
from matplotlib.legend_handler import HandlerTuple  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.markers import TICKUP  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

# Parameters of docs/model.md §2, in the order a legend lists them. eta1 is left out: it
# follows from v, N, m and the forces (or v from it), so it would only repeat them.
MODEL_PARAMETERS = ("N", "M", "m", "k0", "k1", "eta0", "v", "a", "alpha", "F_drive", "F_kin",
                    "chain", "renewal")

# The units a legend writes a parameter in, with each unit's size in SI (metres, ...).
PARAMETER_UNITS = {
    "M": [("kg", 1), ("g", 1e-3)],
    "m": [("kg", 1), ("g", 1e-3), ("mg", 1e-6)],
    "k0": [("N/m", 1)],
    "k1": [("N/m", 1)],
    "eta0": [("1/s", 1)],
    "eta1": [("1/s", 1)],
    "v": [("m/s", 1), ("mm/s", 1e-3), ("µm/s", 1e-6)],
    "a": [("m", 1), ("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9)],
    "F_drive": [("N", 1)],
    "F_kin": [("N", 1)],
    "k_drive": [("N/m", 1)],
}


def _mathtext(symbol):
    """The figures' markup (*italic*, _{subscript}) as matplotlib's mathtext:
    '*η*_{0}' -> '$\\eta_0$', '*F*_{drive}' -> '$F_\\mathrm{drive}$', 'N' -> 'N'."""
    if "*" not in symbol and "_{" not in symbol:
        return symbol

    def italic(match):
        name = unicodedata.name(match.group(1), "")
        return "\\" + name.split()[-1].lower() if name.startswith("GREEK") else match.group(1)

    text = re.sub(r"\*([^*]+)\*", italic, symbol)
    text = re.sub(r"_\{(\d+)\}", r"_\1", text)
    return "$" + re.sub(r"_\{([^}]*)\}", r"_\\mathrm{\1}", text) + "$"


def _read_symbols():
    """{key: mathtext symbol} from parameter_symbols.tsv beside this file (parameters.def's
    symbols, which tests/model/parameters_test.cpp holds it to)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "parameter_symbols.tsv")
    with open(path, encoding="utf-8") as f:
        rows = [line.rstrip("\n").split("\t") for line in f if line.strip() and not line.startswith("#")]
    return {key: _mathtext(symbol) for key, symbol in rows}


PARAMETER_SYMBOLS = _read_symbols()
# Parameters a single run's legend names: the ones the paper's figures vary.
HEADLINE_PARAMETERS = ("N", "v", "a", "alpha")

# The paper's Fig. 2 peak near 4e4 rad/s is absent from the equations as written (docs/model.md §4).
PEAK_NOTE_OMEGA = 1e4
PEAK_NOTE = ("No peak near 4e4 rad/s: the model's equations overdamp the miniblocks "
             "(docs/model.md §4)")

EQ1_ID = "eq1"  # marks the Eq. (1) lines, which share one legend entry
FLOOR_ID = "floor"  # the sensor's noise floor of measured data
FITTED_FLOOR_ID = "fitted_floor"  # the white floor a power-law fit found
FIT_ID = "fit"  # a power law fitted to measured data

# name of the column holding the quantity, y-axis label
KINDS = {
    "displacement": (None, r"$\log_{10}\,C_x$ (m² s)"),
    "velocity": ("C_v", r"$\log_{10}\,C_v$ (m²/s)"),
    "force": ("C_F", r"$\log_{10}\,C_F$ (N² s)"),
}


# The output formats, by the extension of OUT.
FORMATS = ("png", "pdf", "svg")

# gids the tests (and anyone post-processing an SVG) find the parts of a figure by.
THEORY_ID = "theory"  # the exact theory drawn as a line
SIMULATION_ID = "simulation"  # simulated (or measured) points with error bars
RESIDUAL_ID = "residuals"  # the panel of C_x/theory - 1 under run plots


class InputError(Exception):
    """Input that cannot be plotted; the message names the file (if one is to blame) and
    the problem."""


@dataclasses.dataclass
class Spectrum:
    path: str
    metadata: dict  # key -> value string, trailing comments stripped
    columns: dict  # column name -> float array

    def number(self, key):
        """Metadata value as a float, or None when absent or not a number."""
        try:
            return float(self.metadata[key])
        except (KeyError, ValueError):
            return None

    @property
    def simulated(self):
        """`slidespec run` output (points with error bars) rather than a theory table."""
        return "stderr" in self.columns or "theory" in self.columns


def read_spectrum(path):
    """A slidespec TSV (slidespec_tsv's format) as a Spectrum: its KEY = VALUE lines, its columns."""
    try:
        table = slidespec_tsv.read(path)
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read: {getattr(error, 'strerror', None) or error}") from None
    except ValueError as error:
        raise InputError(str(error)) from None
    metadata, header, rows = table.values, table.names, table.rows
    if metadata.get("observable") == "force" and "C_F" in header and "C_x" not in header:
        header = ["C_x" if name == "C_F" else name for name in header]  # the spectrum, whichever observable
    for required in ("omega", "C_x"):
        if required not in header:
            raise InputError(f"{path}: no '{required}' column (columns: {', '.join(header)})")
    if not rows:
        raise InputError(f"{path}: no data rows")
    values = np.array(rows, dtype=float)
    return Spectrum(path, metadata, {name: values[:, i] for i, name in enumerate(header)})


def split_runs(spectrum):
    """A sweep's combined table (a 'run' column and '# run_N = LABEL' lines) as one
    spectrum per run, each with its label and the swept keys' values; any other table as
    itself."""
    if "run" not in spectrum.columns or "run_0" not in spectrum.metadata:
        return [spectrum]
    swept = {key[len("sweep_"):]: value.split() for key, value in spectrum.metadata.items()
             if key.startswith("sweep_")}
    runs = []
    for index in np.unique(spectrum.columns["run"]).astype(int):
        rows = spectrum.columns["run"] == index
        metadata = {key: value for key, value in spectrum.metadata.items()
                    if not key.startswith(("run_", "sweep_"))}
        metadata["label"] = spectrum.metadata.get(f"run_{index}", f"run {index}")
        for key, values in swept.items():
            if key in spectrum.columns:
                value = spectrum.columns[key][rows][0]
                words = not all(_is_float(v) for v in values)
                metadata[key] = values[int(value)] if words else f"{value:.12g}"
        columns = {name: column[rows] for name, column in spectrum.columns.items()
                   if name != "run" and name not in swept}
        runs.append(Spectrum(spectrum.path, metadata, columns))
    return runs


def _is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def _short_number(text):
    """'0.0050000000000000001' -> '5e-3', '30' -> '30'; non-numbers unchanged."""
    try:
        value = float(text)
    except ValueError:
        return text
    if value != 0 and not 1e-2 <= abs(value) < 1e4:
        mantissa, exponent = f"{value:.2e}".split("e")
        return f"{float(mantissa):g}e{int(exponent)}"
    return f"{value:.4g}"


def _same_value(a, b):
    """Compare metadata values as numbers when both are, so '5e-4' equals '0.0005'."""
    try:
        return math.isclose(float(a), float(b), rel_tol=1e-9)
    except ValueError:
        return a == b


def parameter_text(key, value):
    """'v', '5e-4' -> 'v = 0.5 mm/s'; 'alpha', '1' -> 'α = 1' (mathtext)."""
    symbol, units = PARAMETER_SYMBOLS.get(key, key), PARAMETER_UNITS.get(key, [("", 1)])
    try:
        number = float(value)
    except ValueError:
        return f"{symbol} = {value}"
    unit, size = units[-1]
    for candidate, candidate_size in units:  # the largest unit that keeps the number >= 0.1
        if abs(number) >= 0.1 * candidate_size:
            unit, size = candidate, candidate_size
            break
    text = _short_number(repr(number / size))
    return f"{symbol} = {text}" + (f" {unit}" if unit else "")


def _label_keys(label):
    """'reference + N=5, alpha=3' -> ('reference', [('N', '5'), ('alpha', '3')])."""
    name, _, changes = label.partition(" + ")
    pairs = []
    for change in filter(None, (c.strip() for c in changes.split(","))):
        key, _, value = change.partition("=")
        pairs.append((key.strip(), value.strip()))
    return name, pairs


def _literal(text):
    """Text drawn as written: a '$' in a file name does not start mathtext."""
    return text.replace("$", r"\$")


def legend_labels(spectra):
    """Legend text per spectrum: the case (or the 'label' metadata, or the file name) and
    parameters with units and Greek symbols: those that differ between the files, or for
    a single file the ones the paper varies (N, v, a, alpha)."""
    differing = [key for key in MODEL_PARAMETERS
                 if _differ([s.metadata.get(key) for s in spectra])]
    if len(spectra) == 1:
        differing = [key for key in HEADLINE_PARAMETERS if key in spectra[0].metadata]

    labels = []
    for spectrum in spectra:
        label = spectrum.metadata.get("label")
        if label and label.startswith("measured"):
            record = spectrum.metadata.get("record")
            if record:  # the file's name, not its whole path
                label = label.replace(record, os.path.basename(record))
            labels.append(_mark_incomplete(spectrum, _literal(label)))
            continue
        name = _literal(spectrum.metadata.get("case") or os.path.basename(spectrum.path))
        keys = list(differing)
        if label:  # "reference + N=5, alpha=3": the set keys are named too
            name, pairs = _label_keys(label)
            keys += [key for key, _ in pairs if key not in keys and key in spectrum.metadata]
        parameters = [parameter_text(key, spectrum.metadata[key])
                      for key in keys if key in spectrum.metadata]
        text = name + (": " + ", ".join(parameters) if parameters else "")
        labels.append(_mark_incomplete(spectrum, text))
    return labels


def _differ(values):
    """True when a parameter is given somewhere and not the same everywhere."""
    present = [value for value in values if value is not None]
    return bool(present) and (len(present) < len(values)
                              or not all(_same_value(present[0], v) for v in present))


def _mark_incomplete(spectrum, label):
    if spectrum.metadata.get("stationary", "").lower().startswith("false"):
        label = f"{label} (NOT STATIONARY: no spectrum)"
    if spectrum.metadata.get("complete", "").lower() == "false":
        return f"{label} (incomplete)"
    return label


# The observable of a measured table (`slidespec analyze`'s "# observable ="), on its axis.
OBSERVABLE_LABELS = {
    "force": r"$\log_{10}\,C_F$ of the force (N² s)",
    "slip": r"$\log_{10}\,C_x$ of the slip $x - F/K$ (m² s)",
    "displacement": r"$\log_{10}\,C_x$ of the displacement (m² s)",
}


def y_label(spectra, kind):
    """The y axis: the observable of measured tables when they share one, else the kind's."""
    observables = {s.metadata.get("observable") for s in spectra}
    if kind == "displacement" and len(observables) == 1 and observables <= OBSERVABLE_LABELS.keys():
        return OBSERVABLE_LABELS[observables.pop()]
    return KINDS[kind][1]


def kind_factor(spectrum, kind, omega):
    """Factor turning a displacement spectrum into the requested one (docs/model.md §5)."""
    if kind == "velocity":
        return omega ** 2
    if kind == "force":
        mass = spectrum.number("M")
        if mass is None:
            raise InputError(f"{spectrum.path}: no 'M' metadata, needed for --kind force")
        return mass ** 2 * omega ** 4
    return np.ones_like(omega)


def eq1_range(spectrum, omega):
    """Where Eq. (1) applies, v/a << omega << omega_c: 5 v/a to omega_c/3 when known, else
    the middle third (in log omega) of the file's range."""
    v, a, omega_c = spectrum.number("v"), spectrum.number("a"), spectrum.number("omega_c")
    if v and a and omega_c:
        return 5 * v / a, omega_c / 3
    low, high = np.log10(omega.min()), np.log10(omega.max())
    return 10 ** (low + (high - low) / 3), 10 ** (high - (high - low) / 3)


def _log_positive(omega, values):
    """log10 of both, keeping only points where both are positive and finite."""
    keep = np.isfinite(values) & (values > 0) & (omega > 0)
    return np.log10(omega[keep]), np.log10(values[keep]), keep


def read_fine_theory(path):
    """A theory line from the command line: '# omega<TAB>C_x' rows on a fine grid."""
    table = read_spectrum(path)
    return table.columns["omega"], table.columns["C_x"]


def _in_range(omega, args):
    keep = np.ones_like(omega, dtype=bool)
    if args.omega_min is not None:
        keep &= omega >= args.omega_min
    if args.omega_max is not None:
        keep &= omega <= args.omega_max
    return keep


def plot_spectrum(axes, spectrum, label, color, args, fine_theory=None):
    """Draw one file: data as markers with error bars (or a theory table as a line), its
    theory as a line (the fine one when given) and Eq. (1). Returns the omegas in range
    and the legend handle (None when nothing is drawn)."""
    omega = spectrum.columns["omega"]
    in_range = _in_range(omega, args)
    columns = {name: values[in_range] for name, values in spectrum.columns.items()}
    omega = columns["omega"]
    if omega.size == 0:
        return omega, None
    factor = kind_factor(spectrum, args.kind, omega)
    kind_column = KINDS[args.kind][0]
    values = columns[kind_column] if kind_column in columns else columns["C_x"] * factor

    x, y, keep = _log_positive(omega, values)
    if x.size == 0:
        return omega, None
    theory_line = None
    if fine_theory is not None:
        fine_omega, fine_c = fine_theory
        inside = _in_range(fine_omega, args) & (fine_omega >= omega.min() / 1.0001) \
            & (fine_omega <= omega.max() * 1.0001)
        tx, ty, _ = _log_positive(fine_omega[inside],
                                  fine_c[inside] * kind_factor(spectrum, args.kind, fine_omega[inside]))
        (theory_line,) = axes.plot(tx, ty, "-", color=color, linewidth=1.3, zorder=2, gid=THEORY_ID)
    if spectrum.simulated:
        error = None
        if "stderr" in columns:
            error = _log_error_bars(values[keep], (columns["stderr"] * factor)[keep])
        markers = axes.errorbar(x, y, yerr=error, fmt="o", markersize=4, color=color,
                                markeredgecolor="black", markeredgewidth=0.4, ecolor=color,
                                elinewidth=1.0, capsize=2, label=label, zorder=3)
        markers[0].set_gid(SIMULATION_ID)
        if "below_floor" in columns:
            _plot_sensor_limits(axes, spectrum, columns, factor, keep, x, y)
        if theory_line is None and "theory" in columns:
            tx, ty, _ = _log_positive(omega, columns["theory"] * factor)
            (theory_line,) = axes.plot(tx, ty, "-", color=color, linewidth=1.3, zorder=2, gid=THEORY_ID)
        handle = (markers[0], theory_line) if theory_line is not None else markers[0]
    else:
        if theory_line is None:
            (theory_line,) = axes.plot(x, y, "-", color=color, linewidth=1.6, zorder=2, gid=THEORY_ID)
        handle = theory_line

    if not args.no_eq1:
        _plot_eq1(axes, spectrum, columns, factor)
    return omega, handle


def is_run(spectrum):
    """A `slidespec run` table: simulated points, their stderr and the theory beside them."""
    return all(c in spectrum.columns for c in ("stderr", "theory")) and \
        "below_floor" not in spectrum.columns


def plot_residuals(axes, spectrum, color, args, band_alpha=0.18):
    """C_x/theory - 1 with +-1 stderr bars and the +-2 stderr band, for one run."""
    columns = spectrum.columns
    keep = _in_range(columns["omega"], args) & (columns["theory"] > 0) & (columns["omega"] > 0)
    omega, theory = columns["omega"][keep], columns["theory"][keep]
    residual = columns["C_x"][keep] / theory - 1
    relative_error = np.abs(columns["stderr"][keep]) / theory
    x = np.log10(omega)
    axes.fill_between(x, -2 * relative_error, 2 * relative_error, color=color, alpha=band_alpha,
                      linewidth=0, zorder=1)
    axes.errorbar(x, residual, yerr=relative_error, fmt="o", markersize=3, color=color,
                  markeredgecolor="black", markeredgewidth=0.3, elinewidth=0.8, capsize=1.5,
                  zorder=3)
    return np.nanmax(np.abs(residual) + relative_error, initial=0.0)


def plot_fit_residuals(axes, spectrum, color, args):
    """A measured table's fit residuals (C - fit)/sigma inside the fit's band, with the
    +-2 band a correct fit stays in at 95% of points."""
    columns = spectrum.columns
    keep = _in_range(columns["omega"], args) & np.isfinite(columns["residual"]) & (columns["omega"] > 0)
    x, residual = np.log10(columns["omega"][keep]), columns["residual"][keep]
    if x.size:
        axes.fill_between(x, -2, 2, color=color, alpha=0.15, linewidth=0, zorder=1)
        axes.plot(x, residual, "o", markersize=3, color=color, markeredgecolor="black",
                  markeredgewidth=0.3, zorder=3, gid=RESIDUAL_ID)
    return float(np.nanmax(np.abs(residual), initial=0.0))


def _plot_sensor_limits(axes, spectrum, columns, factor, keep, x, y):
    """Measured data (`slidespec analyze`): the sensor's noise floor as a grey dash-dot line
    when one was given (--resolution, --sensor-noise) or fitted (--fit power-law), points
    indistinguishable from a given floor drawn hollow, and a fitted power law if there is one."""
    floor = columns["floor"] * factor
    fitted = spectrum.number("power_law_floor") or spectrum.number("model_fit_floor")
    if np.any(floor > 0):
        below = columns["below_floor"][keep] > 0
        if np.any(below):
            axes.plot(x[below], y[below], "o", markersize=5, markerfacecolor="white",
                      markeredgecolor="0.5", zorder=4, gid=FLOOR_ID)
        fx, fy, _ = _log_positive(columns["omega"], floor)
        if fx.size >= 2:
            axes.plot(fx, fy, "-.", color="0.45", linewidth=1.0, zorder=1, gid=FLOOR_ID)
    elif fitted is not None and fitted > 0:
        # A white floor seen through the estimator's bins is the same white level.
        fx, fy, _ = _log_positive(columns["omega"], np.full_like(columns["omega"], fitted) * factor)
        if fx.size >= 2:
            axes.plot(fx, fy, "-.", color="0.45", linewidth=1.0, zorder=1, gid=FITTED_FLOOR_ID)
    if "fit" in columns:
        sx, sy, _ = _log_positive(columns["omega"], columns["fit"] * factor)
        if sx.size >= 2:
            axes.plot(sx, sy, "-", color="black", linewidth=2.2, alpha=0.45, zorder=5, gid=FIT_ID)


def _log_error_bars(values, stderr):
    """Asymmetric bars in log10 space; a bar reaching zero or below is drawn one decade long,
    a missing (non-finite) stderr as no bar."""
    stderr = np.where(np.isfinite(stderr), np.abs(stderr), 0.0)
    low_end = values - stderr
    with np.errstate(invalid="ignore", divide="ignore"):
        lower = np.where(low_end > 0, np.log10(values / low_end), 1.0)
    return np.vstack([lower, np.log10(1 + stderr / values)])


def _plot_eq1(axes, spectrum, columns, factor):
    omega = columns["omega"]
    if spectrum.number("omega_resonance") is not None:
        return  # a spring's run: Eq. (1) is the constant force's asymptote, above its spectrum
    if "C_eq1" in columns:
        eq1 = columns["C_eq1"]
    elif spectrum.number("eq1_prefactor") is not None:
        eq1 = spectrum.number("eq1_prefactor") / omega ** 4
    else:
        return
    low, high = eq1_range(spectrum, spectrum.columns["omega"])
    inside = (omega >= low) & (omega <= high)
    x, y, _ = _log_positive(omega[inside], (eq1 * factor)[inside])
    if x.size >= 2:
        # Black on top: it lies on the exact curve, so its own colour would hide it.
        axes.plot(x, y, "--", color="black", linewidth=0.9, zorder=4, gid=EQ1_ID)


# The height of the ω_c label (11 pt mathtext, with its descender) in points.
OMEGA_C_LABEL_HEIGHT = 14


def mark_omega_c(axes, spectra, colors):
    """A dotted vertical line labelled ω_c per distinct omega_c (ω_res at a spring's
    omega_resonance, where k_drive stiffens the block); grey when all files agree, else in the
    colour of the first file with that resonance. Returns the height the labels take above
    the axes (points), which a title must clear."""
    marks, labels = {}, {}
    for spectrum, color in zip(spectra, colors):
        spring = spectrum.number("omega_resonance")
        omega_c = spring if spring is not None else spectrum.number("omega_c")
        if omega_c and omega_c > 0 and not any(math.isclose(omega_c, seen, rel_tol=1e-6)
                                               for seen in marks):
            marks[omega_c] = color
            labels[omega_c] = r"$\omega_{\mathrm{res}}$" if spring is not None else r"$\omega_c$"
    if not marks:
        return 0
    line_colors = ["0.4"] if len(marks) == 1 else list(marks.values())
    positions = [math.log10(omega_c) for omega_c in marks]
    texts = list(labels.values())
    for x, color in zip(positions, line_colors):
        axes.axvline(x, linestyle=":", color=color, linewidth=1.2, zorder=0)
    # Labelled as ticks on the top edge, where they cannot collide with data or legend: a
    # tick's mark and label drawn as such (a secondary axis would look the same and cost
    # an eighth of the figure's drawing time in layout).
    edge = axes.get_xaxis_transform()  # x: data, y: axes fraction
    size, pad = matplotlib.rcParams["xtick.major.size"], matplotlib.rcParams["xtick.major.pad"]
    for x, color, text in zip(positions, line_colors, texts):
        axes.add_artist(Line2D([x], [1], transform=edge, marker=TICKUP, markersize=size, clip_on=False,
                               markeredgewidth=matplotlib.rcParams["xtick.major.width"],
                               color=matplotlib.rcParams["xtick.color"]))
        axes.annotate(text, (x, 1), xycoords=edge, xytext=(0, size + pad),
                      textcoords="offset points", ha="center", va="bottom", fontsize=11, color=color)
    return size + pad + OMEGA_C_LABEL_HEIGHT


def _figure_size(args, with_residuals):
    if args.size:
        return args.size
    return (7, 6.2) if with_residuals else (7, 5)


def render(spectra, labels, args, fine_theories=None):
    """Build the figure; returns it without saving so errors leave no output behind."""
    fine_theories = fine_theories or [None] * len(spectra)
    runs = [i for i, s in enumerate(spectra) if is_run(s)]
    fits = [i for i, s in enumerate(spectra) if "residual" in s.columns]
    with_residuals = bool(runs or fits) and not args.no_residuals
    size = _figure_size(args, with_residuals)
    if with_residuals:
        figure, (axes, residual_axes) = plt.subplots(
            2, 1, sharex=True, figsize=size, dpi=args.dpi, layout="constrained",
            gridspec_kw={"height_ratios": (3, 1)})
        residual_axes.set_gid(RESIDUAL_ID)
    else:
        figure, axes = plt.subplots(figsize=size, dpi=args.dpi, layout="constrained")
        residual_axes = None
    axes.xaxis.set_major_locator(MaxNLocator(integer=True))
    axes.yaxis.set_major_locator(MaxNLocator(integer=True))
    colors = args.colors or [f"C{i % 10}" for i in range(len(spectra))]
    colors = [colors[i % len(colors)] for i in range(len(spectra))]
    plotted = [plot_spectrum(axes, s, label, color, args, fine)
               for s, label, color, fine in zip(spectra, labels, colors, fine_theories)]
    omega_c_labels = mark_omega_c(axes, spectra, colors)

    highest = max((omega.max() for omega, _ in plotted if omega.size), default=0)
    if highest > PEAK_NOTE_OMEGA:
        # A footnote below the axes, so it never hides data or the legend.
        figure.get_layout_engine().set(rect=(0, 0.04, 1, 0.96))
        figure.text(0.01, 0.01, PEAK_NOTE, fontsize=8, color="0.3", ha="left", va="bottom")

    bottom = residual_axes if residual_axes is not None else axes
    bottom.set_xlabel(r"$\log_{10}\,\omega$ (rad/s)", fontsize=12)
    axes.set_ylabel(y_label(spectra, args.kind), fontsize=12)
    axes.tick_params(labelsize=10)
    axes.grid(True, color="0.9", linewidth=0.6)
    if args.title:
        axes.set_title(args.title, fontsize=12, pad=matplotlib.rcParams["axes.titlepad"] + omega_c_labels)
    if residual_axes is not None and runs:
        # Overlapping bands of many runs add up: each lighter, so the stack stays readable.
        band_alpha = 0.18 if len(runs) <= 2 else 0.36 / len(runs)
        reach = max(plot_residuals(residual_axes, spectra[i], colors[i], args, band_alpha)
                    for i in runs)
        limit = min(max(1.15 * reach, 0.05), 1.0)
        residual_axes.set_ylim(-limit, limit)
        residual_axes.set_ylabel(r"$C_x/\mathrm{theory} - 1$", fontsize=11)
        residual_axes.text(0.01, 0.95, r"band: $\pm 2$ stderr", transform=residual_axes.transAxes,
                           fontsize=8, color="0.3", va="top")
    elif residual_axes is not None:
        reach = max(plot_fit_residuals(residual_axes, spectra[i], colors[i], args) for i in fits)
        limit = min(max(1.15 * reach, 3.0), 20.0)
        residual_axes.set_ylim(-limit, limit)
        residual_axes.set_ylabel(r"$(C - \mathrm{fit})/\sigma$", fontsize=11)
        residual_axes.text(0.01, 0.95, r"band: $\pm 2\sigma$", transform=residual_axes.transAxes,
                           fontsize=8, color="0.3", va="top")
    if residual_axes is not None:
        residual_axes.axhline(0, color="black", linewidth=0.8, zorder=2)
        residual_axes.grid(True, color="0.9", linewidth=0.6)
        residual_axes.tick_params(labelsize=9)
    handles, texts = [], []
    for (_, handle), label in zip(plotted, labels):  # in file order
        if handle is not None:
            handles.append(handle)
            texts.append(label)
    if not handles:
        raise InputError("nothing to plot: no positive values in the omega range")
    measured = any("below_floor" in s.columns for s in spectra)
    if any(s.simulated for s in spectra):
        handles.append(Line2D([], [], marker="o", linestyle="none", color="0.35",
                              markeredgecolor="black", markeredgewidth=0.4))
        texts.append("measured, ±1 stderr" if measured else "simulation, ±1 stderr")
    if any(line.get_gid() == THEORY_ID for line in axes.lines):
        handles.append(Line2D([], [], color="0.35", linewidth=1.3))
        model = ""
        if measured and spectra[0].metadata.get("case") and "alpha" in spectra[0].metadata:
            meta = spectra[0].metadata
            fitted = (" (fit FAILED)" if "false" in (meta.get("alpha_fit_ok"), meta.get("model_fit_ok"))
                      else " (fitted)" if "fitted_alpha" in meta or "model_fit" in meta else "")
            model = (f": {spectra[0].metadata['case']}, "
                     f"{parameter_text('alpha', spectra[0].metadata['alpha'])}{fitted}")
        texts.append("model theory" + model if measured else "exact first-order theory")
    if any(line.get_gid() == EQ1_ID for line in axes.lines):
        handles.append(Line2D([], [], linestyle="--", color="black", linewidth=0.9))
        texts.append("Eq. (1)")
    if any(line.get_gid() == FLOOR_ID for line in axes.lines):
        handles.append(Line2D([], [], linestyle="-.", color="0.45", marker="o",
                              markerfacecolor="white", markeredgecolor="0.5"))
        texts.append("sensor floor; hollow: at or below it")
    if any(line.get_gid() == FITTED_FLOOR_ID for line in axes.lines):
        handles.append(Line2D([], [], linestyle="-.", color="0.45"))
        texts.append("sensor floor (fitted)")
    if any(line.get_gid() == FIT_ID for line in axes.lines):
        handles.append(Line2D([], [], color="black", linewidth=2.2, alpha=0.45))
        texts.append(fit_legend(spectra[0].metadata))
    axes.legend(handles, texts, fontsize=8.5, loc="best", framealpha=0.85, edgecolor="none",
                handler_map={tuple: HandlerTuple(ndivide=None)})
    return figure


def fit_legend(metadata):
    """The fitted power law's legend entry, marked FAILED (with its chi2/dof) when the fit
    does not describe the data: a failed fit's numbers are no result."""
    slope = (metadata.get("power_law_slope") or metadata.get("slope") or "").split()
    text = f"fit: slope {float(slope[0]):.2f}" if slope and _is_float(slope[0]) else "fit"
    fitted = [(key[len("model_fit_"):], value.split()[0]) for key, value in metadata.items()
              if key in ("model_fit_alpha", "model_fit_a", "model_fit_k_drive")]
    if fitted:
        text = "model fit: " + ", ".join(f"{name} = {float(value):.3g}" for name, value in fitted)
    if "false" in (metadata.get("power_law_fit_ok"), metadata.get("slope_fit_ok"), metadata.get("model_fit_ok")):
        chi2 = re.search(r"chi2/dof ([0-9.eE+-]+)", metadata.get("power_law", "") + metadata.get("slope", "")
                         + metadata.get("model_fit", ""))
        return "fit FAILED" + (f" (chi²/dof {float(chi2.group(1)):.3g})" if chi2 else "") + f", not a result: {text}"
    return text


def output_format(path):
    """The format by OUT's extension; an InputError for any other."""
    extension = os.path.splitext(path)[1].lower().lstrip(".")
    if extension not in FORMATS:
        raise InputError(f"{path}: unknown figure format '.{extension}' (known: .png, .pdf, .svg)")
    return extension


# zlib's fastest level: a figure's PNG is 10% larger and written in a third less time, still
# lossless (the figure is on the critical path of every run).
PNG_COMPRESS_LEVEL = 1


def _one_pass_png(figure, fmt):
    """savefig's arguments for a PNG drawn once: savefig lays a figure out by a drawing pass
    of its own before the pass it encodes, so the layout is done here (the same engine at
    the same dpi, hence the same positions) and switched off."""
    if fmt != "png":
        return {}
    engine = figure.get_layout_engine()
    if engine is not None:
        engine.execute(figure)
        figure.set_layout_engine("none")
    return {"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}}


def save_atomically(figure, out_path, dpi):
    """Write to a temporary file beside OUT, then rename: readers never see half a file."""
    fmt = output_format(out_path)
    directory = os.path.dirname(os.path.abspath(out_path))
    handle = tempfile.NamedTemporaryFile(dir=directory, prefix=".plot_spectra.", suffix="." + fmt,
                                         delete=False)
    try:
        with handle:
            figure.savefig(handle, format=fmt, dpi=dpi, **_one_pass_png(figure, fmt))
        # tempfile creates the file private (0600); a picture is for sharing, as usual.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(handle.name, 0o666 & ~umask)
        os.replace(handle.name, out_path)
    except BaseException:
        os.unlink(handle.name)
        raise


def _size(text):
    match = re.fullmatch(r"\s*([0-9.]+)\s*[xX,]\s*([0-9.]+)\s*", text)
    if not match or not all(0.5 <= float(v) <= 100 for v in match.groups()):
        raise argparse.ArgumentTypeError(f"'{text}' is not WxH in inches (e.g. 7x5)")
    return float(match.group(1)), float(match.group(2))


def _dpi(text):
    try:
        value = float(text)
    except ValueError:
        value = 0
    if not 10 <= value <= 2400:
        raise argparse.ArgumentTypeError(f"'{text}' is not a resolution in dots per inch (10..2400)")
    return value


def check_title(title):
    """An InputError for a title whose $...$ matplotlib cannot typeset (found before drawing).
    An even number of unescaped dollar signs makes matplotlib read the title as mathtext."""
    if not title or len(re.findall(r"(?<!\\)\$", title)) % 2 or "$" not in title:
        return
    from matplotlib.mathtext import MathTextParser
    try:
        MathTextParser("path").parse(title)
    except ValueError as error:
        reason = " ".join(str(error).split())
        raise InputError(f"--title: matplotlib cannot typeset {title!r} ({reason[:200]}); "
                         "escape a literal dollar as \\$") from None


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description="Plot slidespec spectra (TSV) to PNG, PDF or SVG.")
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("-o", "--out", required=True, metavar="OUT.{png,pdf,svg}")
    parser.add_argument("--title")
    parser.add_argument("--labels", help="comma-separated legend entries, one per FILE")
    parser.add_argument("--theory", help="comma-separated fine theory tables, one per FILE "
                        "('-' for none): drawn as the theory line")
    parser.add_argument("--colors", help="comma-separated matplotlib colours, one per FILE")
    parser.add_argument("--size", type=_size, metavar="WxH", help="inches (default 7x5, 7x6.2 "
                        "with the residual panel)")
    parser.add_argument("--dpi", type=_dpi, default=150.0, help="dots per inch (default 150)")
    parser.add_argument("--no-residuals", action="store_true",
                        help="no C_x/theory - 1 panel under run tables")
    parser.add_argument("--omega-min", type=float, metavar="W")
    parser.add_argument("--omega-max", type=float, metavar="W")
    parser.add_argument("--no-eq1", action="store_true", help="leave out the Eq. (1) asymptote")
    parser.add_argument("--kind", choices=tuple(KINDS), default="displacement")
    parser.add_argument("--layout", choices=("standard", "drives"), default="standard",
                        help="drives: the drives figure of plot_drives.py")
    args = parser.parse_args(argv)
    for option in ("labels", "theory", "colors"):
        value = getattr(args, option)
        if value is not None and len(value.split(",")) != len(args.files) and option != "colors":
            parser.error(f"--{option} has {len(value.split(','))} entries for "
                         f"{len(args.files)} files")
    args.colors = args.colors.split(",") if args.colors else None
    return args


def main(argv=None):
    args = parse_arguments(argv)
    try:
        output_format(args.out)
        check_title(args.title)
        spectra = [run for path in args.files for run in split_runs(read_spectrum(path))]
        fine = [None if not path or path == "-" else read_fine_theory(path)
                for path in (args.theory.split(",") if args.theory else [])] or None
        if args.labels is not None:
            labels = [_mark_incomplete(s, label.strip())
                      for s, label in zip(spectra, args.labels.split(","))]
        else:
            labels = legend_labels(spectra)
        if args.layout == "drives":
            import plot_drives  # pylint: disable=import-outside-toplevel
            figure = plot_drives.render(spectra, labels, args, fine)
        else:
            figure = render(spectra, labels, args, fine)
    except InputError as error:
        print(f"plot_spectra: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"plot_spectra: {error.filename or ''}: cannot read: {error.strerror or error}",
              file=sys.stderr)
        return 2
    # The inputs were good: a figure that cannot be written is a failure, not bad input.
    try:
        save_atomically(figure, args.out, args.dpi)
    except OSError as error:
        print(f"plot_spectra: {args.out}: cannot write: {error.strerror or error}",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
