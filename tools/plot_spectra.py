#!/usr/bin/env python3
"""Plot slidespec spectrum tables (theory or simulated) as log10 C against log10 omega.

Usage: plot_spectra.py FILE [FILE ...] -o OUT.png [--title T] [--labels A,B,...]
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

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (must follow the backend choice)
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

# Parameters of MODEL.md section 2, in the order a legend lists them. eta1 is left out: it
# follows from v, N, m and the forces (or v from it), so it would only repeat them.
MODEL_PARAMETERS = ("N", "M", "m", "k0", "k1", "eta0", "v", "a", "alpha", "F_drive", "F_kin",
                    "chain", "renewal")

# The paper's Fig. 2 peak near 4e4 rad/s is absent from the equations as written (MODEL.md 4).
PEAK_NOTE_OMEGA = 1e4
PEAK_NOTE = ("No peak near 4e4 rad/s: the model's equations overdamp the miniblocks "
             "(docs/model.md)")

EQ1_ID = "eq1"  # marks the Eq. (1) lines, which share one legend entry
FLOOR_ID = "floor"  # the sensor's noise floor of measured data
FIT_ID = "fit"  # a power law fitted to measured data

# name of the column holding the quantity, y-axis label
KINDS = {
    "displacement": (None, r"$\log_{10}\,C_x$ (m² s)"),
    "velocity": ("C_v", r"$\log_{10}\,C_v$ (m²/s)"),
    "force": ("C_F", r"$\log_{10}\,C_F$ (N² s)"),
}

METADATA_LINE = re.compile(r"#\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*)$")
TRAILING_COMMENT = re.compile(r"\s{2,}#.*$")


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
    """Parse a slidespec TSV: '#' metadata/comments, one header line, rows of numbers."""
    try:
        with open(path, encoding="utf-8") as handle:
            lines = handle.read().splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read: {getattr(error, 'strerror', None) or error}")

    metadata, header, rows = {}, None, []
    for line_number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        if line.startswith("#"):
            match = METADATA_LINE.match(line)
            if match and header is None:
                metadata[match.group(1)] = TRAILING_COMMENT.sub("", match.group(2)).strip()
            continue
        fields = line.split("\t")
        if header is None:
            header = [field.strip() for field in fields]
            continue
        if len(fields) != len(header):
            raise InputError(f"{path}: line {line_number}: {len(fields)} fields, "
                             f"header has {len(header)}")
        try:
            rows.append([float(field) for field in fields])
        except ValueError:
            bad = next(f for f in fields if not _is_float(f))
            raise InputError(f"{path}: line {line_number}: '{bad.strip()}' is not a number")

    if header is None:
        raise InputError(f"{path}: no column header line")
    for required in ("omega", "C_x"):
        if required not in header:
            raise InputError(f"{path}: no '{required}' column (columns: {', '.join(header)})")
    if not rows:
        raise InputError(f"{path}: no data rows")
    table = np.array(rows, dtype=float)
    return Spectrum(path, metadata, {name: table[:, i] for i, name in enumerate(header)})


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


def legend_labels(spectra):
    """Legend text per spectrum: the 'label' metadata, else the case name (or, without one,
    the file name) followed by the model parameters that differ between the files."""
    differing = [key for key in MODEL_PARAMETERS
                 if _differ([s.metadata.get(key) for s in spectra])]

    labels = []
    for spectrum in spectra:
        label = spectrum.metadata.get("label")
        if not label:
            name = spectrum.metadata.get("case") or os.path.basename(spectrum.path)
            parameters = [f"{key} = {_short_number(spectrum.metadata[key])}"
                          for key in differing if key in spectrum.metadata]
            label = ", ".join([name] + parameters)
        labels.append(_mark_incomplete(spectrum, label))
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


def kind_factor(spectrum, kind, omega):
    """Factor turning a displacement spectrum into the requested one (MODEL.md 5)."""
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


def plot_spectrum(axes, spectrum, label, color, args):
    """Draw one file: data (points with error bars, or a line), its theory and Eq. (1).
    Returns the omegas in range and the artist for the legend (None when nothing is drawn)."""
    omega = spectrum.columns["omega"]
    in_range = np.ones_like(omega, dtype=bool)
    if args.omega_min is not None:
        in_range &= omega >= args.omega_min
    if args.omega_max is not None:
        in_range &= omega <= args.omega_max
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
    if spectrum.simulated:
        error = None
        if "stderr" in columns:
            error = _log_error_bars(values[keep], (columns["stderr"] * factor)[keep])
        handle = axes.errorbar(x, y, yerr=error, fmt="o", markersize=3, color=color,
                               elinewidth=0.8, capsize=0, label=label, zorder=3)
        if "below_floor" in columns:
            _plot_sensor_limits(axes, columns, factor, keep, x, y)
        if "theory" in columns:
            tx, ty, _ = _log_positive(omega, columns["theory"] * factor)
            axes.plot(tx, ty, "-", color=color, linewidth=1.2, zorder=2)
    else:
        (handle,) = axes.plot(x, y, "-", color=color, linewidth=1.6, label=label, zorder=2)

    if not args.no_eq1:
        _plot_eq1(axes, spectrum, columns, factor)
    return omega, handle


def _plot_sensor_limits(axes, columns, factor, keep, x, y):
    """Measured data (`slidespec analyze`): the sensor's noise floor as a grey dash-dot line,
    points indistinguishable from it drawn hollow, and a fitted power law if there is one."""
    below = columns["below_floor"][keep] > 0
    axes.plot(x[below], y[below], "o", markersize=5, markerfacecolor="white",
              markeredgecolor="0.5", zorder=4, gid=FLOOR_ID)
    fx, fy, _ = _log_positive(columns["omega"], columns["floor"] * factor)
    if fx.size >= 2:
        axes.plot(fx, fy, "-.", color="0.45", linewidth=1.0, zorder=1, gid=FLOOR_ID)
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


def mark_omega_c(axes, spectra, colors):
    """A dotted vertical line labelled ω_c per distinct omega_c; grey when all files agree,
    else in the colour of the first file with that omega_c."""
    marks = {}
    for spectrum, color in zip(spectra, colors):
        omega_c = spectrum.number("omega_c")
        if omega_c and omega_c > 0 and not any(math.isclose(omega_c, seen, rel_tol=1e-6)
                                               for seen in marks):
            marks[omega_c] = color
    if not marks:
        return
    line_colors = ["0.4"] if len(marks) == 1 else list(marks.values())
    positions = [math.log10(omega_c) for omega_c in marks]
    for x, color in zip(positions, line_colors):
        axes.axvline(x, linestyle=":", color=color, linewidth=1.2, zorder=0)
    # Labelled as ticks on the top edge, where they cannot collide with data or legend.
    top = axes.secondary_xaxis("top")
    top.set_xticks(positions, [r"$\omega_c$"] * len(positions), fontsize=11)
    for label, color in zip(top.get_xticklabels(), line_colors):
        label.set_color(color)


def render(spectra, labels, args):
    """Build the figure; returns it without saving so errors leave no output behind."""
    figure, axes = plt.subplots(figsize=(7, 5), dpi=150, layout="constrained")
    axes.xaxis.set_major_locator(MaxNLocator(integer=True))
    axes.yaxis.set_major_locator(MaxNLocator(integer=True))
    colors = [f"C{i % 10}" for i in range(len(spectra))]
    plotted = [plot_spectrum(axes, s, label, color, args)
               for s, label, color in zip(spectra, labels, colors)]
    mark_omega_c(axes, spectra, colors)

    highest = max((omega.max() for omega, _ in plotted if omega.size), default=0)
    if highest > PEAK_NOTE_OMEGA:
        # A footnote below the axes, so it never hides data or the legend.
        figure.get_layout_engine().set(rect=(0, 0.04, 1, 0.96))
        figure.text(0.01, 0.01, PEAK_NOTE, fontsize=8, color="0.3", ha="left", va="bottom")

    axes.set_xlabel(r"$\log_{10}\,\omega$ (rad/s)", fontsize=12)
    axes.set_ylabel(KINDS[args.kind][1], fontsize=12)
    axes.tick_params(labelsize=10)
    axes.grid(True, color="0.9", linewidth=0.6)
    if args.title:
        axes.set_title(args.title, fontsize=12)
    handles = [handle for _, handle in plotted if handle is not None]  # in file order
    if not handles:
        raise InputError("nothing to plot: no positive values in the omega range")
    if any(line.get_gid() == EQ1_ID for line in axes.lines):
        handles.append(Line2D([], [], linestyle="--", color="black", linewidth=0.9,
                              label="Eq. (1)"))
    if any(line.get_gid() == FLOOR_ID for line in axes.lines):
        handles.append(Line2D([], [], linestyle="-.", color="0.45", marker="o",
                              markerfacecolor="white", markeredgecolor="0.5",
                              label="sensor floor; hollow: at or below it"))
    if any(line.get_gid() == FIT_ID for line in axes.lines):
        slope = spectra[0].metadata.get("slope", "").split()
        text = f"fit: slope {float(slope[0]):.2f}" if slope and _is_float(slope[0]) else "fit"
        handles.append(Line2D([], [], color="black", linewidth=2.2, alpha=0.45, label=text))
    axes.legend(handles=handles, fontsize=9, loc="best", framealpha=0.85, edgecolor="none")
    return figure


def save_atomically(figure, out_path):
    """Write to a temporary file beside OUT, then rename: readers never see half a PNG."""
    directory = os.path.dirname(os.path.abspath(out_path))
    handle = tempfile.NamedTemporaryFile(dir=directory, prefix=".plot_spectra.", suffix=".png",
                                         delete=False)
    try:
        with handle:
            figure.savefig(handle, format="png", dpi=150)
        # tempfile creates the file private (0600); a picture is for sharing, as usual.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(handle.name, 0o666 & ~umask)
        os.replace(handle.name, out_path)
    except BaseException:
        os.unlink(handle.name)
        raise


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description="Plot slidespec spectra (TSV) to a PNG.")
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("-o", "--out", required=True, metavar="OUT.png")
    parser.add_argument("--title")
    parser.add_argument("--labels", help="comma-separated legend entries, one per FILE")
    parser.add_argument("--omega-min", type=float, metavar="W")
    parser.add_argument("--omega-max", type=float, metavar="W")
    parser.add_argument("--no-eq1", action="store_true", help="leave out the Eq. (1) asymptote")
    parser.add_argument("--kind", choices=tuple(KINDS), default="displacement")
    args = parser.parse_args(argv)
    if args.labels is not None and len(args.labels.split(",")) != len(args.files):
        parser.error(f"--labels has {len(args.labels.split(','))} entries for "
                     f"{len(args.files)} files")
    return args


def main(argv=None):
    args = parse_arguments(argv)
    try:
        spectra = [read_spectrum(path) for path in args.files]
        if args.labels is not None:
            labels = [_mark_incomplete(s, label.strip())
                      for s, label in zip(spectra, args.labels.split(","))]
        else:
            labels = legend_labels(spectra)
        figure = render(spectra, labels, args)
        save_atomically(figure, args.out)
    except InputError as error:
        print(f"plot_spectra: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"plot_spectra: {args.out}: cannot write: {error.strerror or error}",
              file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
