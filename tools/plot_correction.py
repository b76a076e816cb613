#!/usr/bin/python3
"""The measured departure from the first-order theory, C_x/theory - 1 with its standard error
(a run's columns correction and correction_stderr), beside the theory beyond first order
(theory2/theory - 1), for one or more runs of `slidespec run`.

Usage: /usr/bin/python3 tools/plot_correction.py RUN.tsv [RUN.tsv ...] OUT.png

docs/run.md shows the reference case at 0.2% a point (docs/correction.png): the shadow
control variate resolves the eps^2 effects (+0.9% at 0.1 rad/s, -0.28% above v/a) in seconds.
Exit status 2 and one line on stderr for an unusable input; the image is written atomically.
"""

import os
import sys
import tempfile

import slidespec_tsv  # beside this file


def read_run(path):
    """The columns of a run's TSV (numbers) and its label."""
    try:
        table = slidespec_tsv.read(path)
    except ValueError as error:
        raise ValueError(f"{error} (slidespec run writes PREFIX.tsv)") from None
    if "correction" not in table.names:
        raise ValueError(f"{path}: not a run's TSV with a correction column (slidespec run writes PREFIX.tsv)")
    label = table.values.get("label", table.values.get("case", os.path.basename(path)))
    return label, table.columns()


def main(argv):
    if len(argv) < 3 or not argv[-1].endswith(".png"):
        raise ValueError("usage: plot_correction.py RUN.tsv [RUN.tsv ...] OUT.png")
    out = argv[-1]
    if any(os.path.abspath(out) == os.path.abspath(path) for path in argv[1:-1]):
        raise ValueError(f"{out}: the output would replace an input")
    runs = [read_run(path) for path in argv[1:-1]]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for k, (label, c) in enumerate(runs):
        color = f"C{k}"
        percent = [100 * x for x in c["correction"]]
        error = [100 * x for x in c["correction_stderr"]]
        ax.errorbar(c["omega"], percent, yerr=error, fmt="o", ms=3.5, color=color, capsize=2,
                    label=f"{label}: C_x/theory - 1, ±1 stderr")
        # theory2 only where the run says it holds (theory_kind 2 second order, 3 quasi-static),
        # broken where it does not.
        kinds = c.get("theory_kind", [2.0] * len(c["omega"]))
        second = [100 * (t2 / t - 1) if k in (2.0, 3.0) else float("nan")
                  for t2, t, k in zip(c["theory2"], c["theory"], kinds)]
        if any(x == x for x in second):
            name = "quasi-static" if 3.0 in kinds else "second order"
            ax.plot(c["omega"], second, "-", color=color, lw=1.2,
                    label=f"{name} where it holds: theory2/theory - 1 (docs/model.md §7)")
    ax.axhline(0, color="black", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("ω (rad/s)")
    ax.set_ylabel("departure from the first order (%)")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    handle, temporary = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)), suffix=".png")
    os.close(handle)
    try:
        fig.savefig(temporary, dpi=130)
        os.replace(temporary, out)
    except BaseException:
        os.unlink(temporary)
        raise


if __name__ == "__main__":
    try:
        main(sys.argv)
    except (OSError, ValueError) as error:
        print(f"plot_correction: {error}", file=sys.stderr)
        sys.exit(2)
