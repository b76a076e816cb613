#!/usr/bin/env python3
"""Plot the spectrum map of docs/model.md §7 from spectrum_map's TSV.

Usage: plot_spectrum_map.py MAP.tsv OUT.png

The largest deviation of the first- and second-order theory from simulated spectra
(0.05 .. 50 rad/s) against eps, poisson and periodic renewal, with four standard errors of
a point for scale. Exit status 2 and one line on stderr for an unusable input; the image
is written atomically.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (must follow the backend choice)

import map_table  # noqa: E402  (beside this script)

COLUMNS = ("renewal", "eps", "deviation_1", "deviation_2", "beyond_1", "beyond_2", "points", "standard_error")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_spectrum_map.py MAP.tsv OUT.png")
    try:
        data = map_table.read(sys.argv[1], COLUMNS, "spectrum_map")
    except (OSError, ValueError) as error:
        print(f"plot_spectrum_map: {error}", file=sys.stderr)
        sys.exit(2)
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for kind, color in (("poisson", "tab:blue"), ("periodic", "tab:red")):
        if kind not in data:
            continue
        t = data[kind]
        ax.plot(t["eps"], 100 * t["deviation_1"], "o:", color=color, label=f"{kind}: first order")
        ax.plot(t["eps"], 100 * t["deviation_2"], "s-", color=color, label=f"{kind}: second order")
        ax.plot(t["eps"], 400 * t["standard_error"], color=color, lw=3, alpha=0.25, label=f"{kind}: 4 standard errors")
    ax.axvline(1 / 3, color="grey", lw=0.8)
    ax.text(1 / 3, 0.5, " stall", color="grey", rotation=90, va="bottom", transform=ax.get_xaxis_transform())
    ax.set_yscale("log")
    ax.set_xlabel("eps = alpha F_kin / ((F_drive - F_kin) sqrt(6 N))")
    ax.set_ylabel("largest |C_x / theory - 1| over 0.05..50 rad/s [%]")
    ax.set_title("N = 6: simulated spectra against first- and second-order theory")
    ax.legend(fontsize=7)
    fig.tight_layout()
    map_table.save(fig, sys.argv[2])

if __name__ == "__main__":
    main()
