#!/usr/bin/env python3
"""Plot the long-time map of docs/model.md §7 from long_time_map's TSV.

Usage: plot_long_time_map.py MAP.tsv OUT.png

Top: D / D_1 and V / v against eps, simulated (error bars: one standard error) and from
the first-order, second-order and exact quasi-static theory. Bottom: each theory's
deviation from the simulation, in standard errors. Exit status 2 and one line on stderr
for an unusable input; the image is written atomically.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (must follow the backend choice)
import numpy as np  # noqa: E402

import map_table  # noqa: E402  (beside this script)

COLUMNS = ("renewal", "eps", "V_sim", "V_err", "V_1", "V_2", "V_qs", "D_sim", "D_err", "D_1", "D_2", "D_qs")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_long_time_map.py MAP.tsv OUT.png")
    try:
        data = map_table.read(sys.argv[1], COLUMNS, "long_time_map")
    except (OSError, ValueError) as error:
        print(f"plot_long_time_map: {error}", file=sys.stderr)
        sys.exit(2)
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    for column, (kind, t) in enumerate(sorted(data.items(), reverse=True)):
        eps = t["eps"]
        top, bottom = axes[0][column], axes[1][column]
        top.errorbar(eps, t["D_sim"] / t["D_1"], t["D_err"] / t["D_1"], fmt="o", color="k", label="D / D_1 simulated")
        top.plot(eps, t["D_2"] / t["D_1"], "--", color="tab:blue", label="D / D_1 second order")
        top.plot(eps, t["D_qs"] / t["D_1"], "-", color="tab:blue", label="D / D_1 exact quasi-static")
        top.errorbar(eps, t["V_sim"] / t["V_1"], t["V_err"] / t["V_1"], fmt="s", color="tab:red", label="V / v simulated")
        top.plot(eps, 1 / (1 + eps**2 / 2), ":", color="tab:red", label="V / v = 1 / (1 + eps^2/2)")
        top.plot(eps, t["V_2"] / t["V_1"], "--", color="tab:red", label="V / v second order")
        top.plot(eps, t["V_qs"] / t["V_1"], "-", color="tab:red", label="V / v exact quasi-static")
        top.axhline(1, color="grey", lw=0.5)
        top.set_title(f"N = 6, renewal = {kind} (stall at eps = 1/3)")
        top.set_ylabel("ratio to first order")
        for name, style, color in (("D_1", "o:", "k"), ("D_2", "o--", "tab:blue"), ("D_qs", "o-", "tab:blue")):
            bottom.plot(eps, np.abs(t[name] / t["D_sim"] - 1) * 100, style, color=color, label=f"|{name} / D_sim - 1|")
        v_first = 1 / (1 + eps**2 / 2) * t["V_1"]
        for values, name, style in ((t["V_1"], "v", "s:"), (v_first, "v/(1+e)", "s-."),
                                    (t["V_2"], "V_2", "s--"), (t["V_qs"], "V_qs", "s-")):
            bottom.plot(eps, np.abs(values / t["V_sim"] - 1) * 100, style, color="tab:red", label=f"|{name} / V_sim - 1|")
        bottom.plot(eps, 100 * 2 * t["D_err"] / t["D_sim"], color="grey", lw=3, alpha=0.4, label="2 standard errors (D)")
        bottom.plot(eps, 100 * 2 * t["V_err"] / t["V_sim"], color="tab:red", lw=3, alpha=0.25, label="2 standard errors (V)")
        bottom.set_yscale("log")
        bottom.set_xlabel("eps = alpha F_kin / ((F_drive - F_kin) sqrt(6 N))")
        bottom.set_ylabel("deviation from simulation [%]")
    axes[0][0].legend(fontsize=7)
    axes[1][0].legend(fontsize=7)
    fig.tight_layout()
    map_table.save(fig, sys.argv[2])

if __name__ == "__main__":
    main()
