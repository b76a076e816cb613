#!/usr/bin/env python3
"""The validity map of docs/model.md §7.4: where the first- and second-order spectra meet
the simulation.

Usage: validity_map.py run SLIDESPEC TABLE.tsv [--precision P] [--quick]
       validity_map.py plot TABLE.tsv OUT.png
       validity_map.py summary TABLE.tsv

`run` simulates, with `SLIDESPEC run --precision P` (one thread, 0.02 .. 36 rad/s, 4 points
a decade), N in {2, 3, 4, 6, 12, 30}, eps from 0.05 (periodic renewal: 0.0125) to 0.95 of
the stall boundary
(eps_stall = sqrt(2 / (3 N)) with the reference forces), poisson and periodic renewal,
open and ring chains (ring from N = 3), and writes, per run and point range (below v/a,
around it, the omega^-4 range, all), the worst deviation of `theory` (first order),
`theory2` (second order) and, for poisson renewal, the quasi-static spectrum of
docs/model.md §7.5 (the run's `theory` times the ratio of tools/quasi_static.py) in standard errors and in per cent, and the fraction of points
within 2 standard errors. `theory2` is the run's where it offers one; for poisson renewal
beyond the run's eps limit it is the run's `theory` times the second- over first-order
ratio of `SLIDESPEC theory --order 2` at the point's omega (column theory2_source), which
the map needs to place that limit. `--quick` runs a reduced grid. Rows are appended as
each run ends and a finished (renewal, chain, N, eps) is not run again, so an interrupted
map resumes. `plot` draws the table; `summary` prints it as the Markdown table of
docs/model.md §7.4 (over all points; open and ring runs pooled: the same process). Exit status 2 and one line on stderr for an unusable
input; the table and the image are written atomically.
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

import map_table  # noqa: E402  (beside this script)
import quasi_static  # noqa: E402

COLUMNS = ("renewal", "chain", "N", "eps", "eps_stall", "range", "points", "dev1_sigma", "dev1_percent",
           "within2_1", "dev2_sigma", "dev2_percent", "within2_2", "theory2_source", "reached_precision",
           "stationary", "mean_speed_ratio", "dev3_sigma", "dev3_percent", "within2_3")
NS = (2, 3, 4, 6, 12, 30)
# The simulation lumps the chain (docs/numerics.md): open and ring ends give the same
# process, so the ring runs, with their own seed, are an independent second sample.
SEEDS = {"open": "27", "ring": "28"}
EPS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55)
# The first order's zeros put periodic renewal's first-order limit below 0.05.
SMALL_EPS = {"poisson": (), "periodic": (0.0125, 0.025)}
DRIVE_EXCESS = 5.0  # F_drive - F_kin of the reference case [N]; F_kin is 5 N too
OMEGA_MIN, OMEGA_MAX, POINTS = 0.02, 36, 4
# Point ranges in units of the renewal rate v/a (0.5 1/s in the reference case).
RANGES = (("below", 0, 0.5), ("around", 0.5, 10), ("omega^-4", 10, math.inf), ("all", 0, math.inf))


def eps_stall(n):
    """The stall boundary alpha F_kin = 2 (F_drive - F_kin) in eps, for the reference forces."""
    return 2 / math.sqrt(6 * n)


def grid(quick):
    ns = (3, 6, 30) if quick else NS
    for chain in ("open", "ring"):
        for renewal in ("poisson", "periodic"):
            for n in ns:
                if chain == "ring" and n < 3:
                    continue
                stall = eps_stall(n)
                values = [*SMALL_EPS[renewal], *(e for e in EPS if e < 0.92 * stall), round(0.95 * stall, 4)]
                for eps in values:
                    yield renewal, chain, n, eps


def read_tsv(path):
    """Header values (`# key = value`) and the data columns of a slidespec TSV."""
    header, names, rows = {}, None, []
    with open(path) as f:
        for line in f:
            if line.startswith("# omega\t") or line.startswith("omega\t"):
                names = line.lstrip("# ").rstrip("\n").split("\t")
            elif line.startswith("#"):
                key, _, value = line[1:].partition("=")
                header[key.strip()] = value.split("#")[0].strip()
            elif line.strip():
                rows.append([float(x) for x in line.split("\t")])
    if names is None:
        raise ValueError(f"{path}: no column header")
    return header, {name: [r[i] for r in rows] for i, name in enumerate(names)}


def simulate(slidespec, work, renewal, chain, n, eps, precision):
    alpha = eps * math.sqrt(6 * n)
    sets = ["--set", f"N={n}", "--set", f"alpha={alpha:.10g}", "--set", f"renewal={renewal}", "--set",
            f"chain={chain}"]
    span = ["--omega-min", str(OMEGA_MIN), "--omega-max", str(OMEGA_MAX), "--points", str(POINTS)]
    prefix = os.path.join(work, "run")
    subprocess.run(["nice", "-n", "10", slidespec, "run", *sets, *span, "--precision", str(precision), "--seed", SEEDS[chain],
                    "--threads", "1", "--out", prefix, "--no-plot", "--quiet"], check=False)
    if not os.path.exists(prefix + ".tsv"):
        raise ValueError(f"{renewal} {chain} N={n} eps={eps}: the run wrote no table")
    header, data = read_tsv(prefix + ".tsv")
    source = "run"
    if header.get("theory_kind") == "quasi_static":
        data["theory2"] = [math.nan] * len(data["theory2"])  # the run's theory2 is the quasi-static one
    if all(math.isnan(x) for x in data["theory2"]):
        source = "none"
        if renewal == "poisson":
            subprocess.run([slidespec, "theory", *sets, *span, "--order", "2", "--out", prefix + "_theory"],
                           check=True, stderr=subprocess.DEVNULL)
            _, theory = read_tsv(prefix + "_theory.tsv")
            data["theory2"] = [t * c2 / c1 for t, c1, c2 in zip(data["theory"], theory["C_x"], theory["C_x2"])]
            source = "ratio"
    # The quasi-static spectrum (poisson, below the stall): the run's first order times the
    # ratio of tools/quasi_static.py at the point's omega (smooth, so the bin average).
    data["theory3"] = [math.nan] * len(data["theory"])
    if renewal == "poisson" and eps < eps_stall(n):
        rate = 0.5  # v/a [1/s], the reference case's
        ratio = quasi_static.QuasiStatic(n, eps).ratio([w / rate for w in data["omega"]])
        data["theory3"] = [t * r for t, r in zip(data["theory"], ratio)]
    return header, data, source


def deviations(values, data, keep):
    sigmas = [abs(c - t) / s for c, t, s, k in zip(data["C_x"], values, data["stderr"], keep) if k]
    percents = [100 * abs(c / t - 1) for c, t, k in zip(data["C_x"], values, keep) if k]
    if not sigmas or any(math.isnan(x) for x in sigmas):
        return math.nan, math.nan, math.nan
    return max(sigmas), max(percents), sum(x <= 2 for x in sigmas) / len(sigmas)


def rows_of(renewal, chain, n, eps, header, data, source):
    rate = 0.5  # v/a [1/s], the reference case's
    out = []
    for name, low, high in RANGES:
        keep = [low <= w / rate < high for w in data["omega"]]
        d1 = deviations(data["theory"], data, keep)
        d2 = deviations(data["theory2"], data, keep)
        d3 = deviations(data["theory3"], data, keep)
        speed = float(header["measured_mean_speed"]) / float(header["v"])
        out.append((renewal, chain, n, eps, round(eps_stall(n), 4), name, sum(keep), *d1[:2], d1[2], *d2[:2], d2[2],
                    source, float(header["reached_precision"]), header["stationary"], speed, *d3[:2], d3[2]))
    return out


def fmt(x):
    return f"{x:.4g}" if isinstance(x, float) else str(x)


def run(args):
    done = set()
    lines = []
    if os.path.exists(args.table):
        with open(args.table) as f:
            lines = [line for line in f if line.strip()]
        if not lines or tuple(lines[0].rstrip("\n").split("\t")) != COLUMNS:
            raise ValueError(f"{args.table}: not a validity_map table (header {COLUMNS})")
        for line in lines[1:]:
            f = line.split("\t")
            done.add((f[0], f[1], int(f[2]), float(f[3])))
    else:
        lines = ["\t".join(COLUMNS) + "\n"]
    with tempfile.TemporaryDirectory() as work:
        for renewal, chain, n, eps in grid(args.quick):
            if (renewal, chain, n, eps) in done:
                continue
            header, data, source = simulate(args.slidespec, work, renewal, chain, n, eps, args.precision)
            lines += ["\t".join(fmt(x) for x in row) + "\n" for row in rows_of(renewal, chain, n, eps, header, data,
                                                                               source)]
            write_atomically(args.table, lines)
            print(f"{renewal} {chain} N={n} eps={eps}: done", file=sys.stderr, flush=True)


def write_atomically(path, lines):
    handle, temporary = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)))
    with os.fdopen(handle, "w") as f:
        f.writelines(lines)
    os.replace(temporary, path)


def read_table(path):
    with open(path) as f:
        lines = [line.rstrip("\n").split("\t") for line in f if line.strip()]
    if not lines or tuple(lines[0]) != COLUMNS:
        raise ValueError(f"{path}: not a validity_map table (header {COLUMNS})")
    return [dict(zip(COLUMNS, r)) for r in lines[1:]]


def summary(args):
    rows = [r for r in read_table(args.table) if r["range"] == "all"]
    print("| renewal | N | eps | eps / eps_stall | first order: worst (stderr, %); within 2 stderr |"
          " second order: worst (stderr, %); within 2 stderr | quasi-static (§7.5) |")
    print("|---|---|---|---|---|---|---|")
    keys = sorted({(r["renewal"], int(r["N"]), float(r["eps"])) for r in rows}, key=lambda k: (k[0] != "poisson", k[1:]))
    for renewal, n, eps in keys:
        runs = [r for r in rows if (r["renewal"], int(r["N"]), float(r["eps"])) == (renewal, n, eps)]
        cells = []
        for order in ("1", "2", "3"):
            sigma = max(float(r[f"dev{order}_sigma"]) for r in runs)
            if math.isnan(sigma):
                cells.append("not computed" if order != "3" or renewal == "poisson" else "not derived")
                continue
            percent = max(float(r[f"dev{order}_percent"]) for r in runs)
            within = sum(float(r[f"within2_{order}"]) * int(r["points"]) for r in runs) / sum(
                int(r["points"]) for r in runs)
            cells.append(f"{sigma:.1f}, {percent:.1f}%; {100 * within:.0f}%")
        print(f"| {renewal} | {n} | {eps:g} | {eps / eps_stall(n):.2f} | {cells[0]} | {cells[1]} | {cells[2]} |")


def plot(args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in read_table(args.table) if r["chain"] == "open" and r["range"] == "all"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8), sharex=True)
    colors = dict(zip(NS, ("tab:purple", "tab:blue", "tab:cyan", "tab:green", "tab:orange", "tab:red")))
    for column, renewal in enumerate(("poisson", "periodic")):
        top, bottom = axes[0][column], axes[1][column]
        for n in NS:
            r = sorted((float(x["eps"]), x) for x in rows if x["renewal"] == renewal and int(x["N"]) == n)
            if not r:
                continue
            ratio = [e / eps_stall(n) for e, _ in r]
            for order, style in (("1", "o:"), ("2", "s-"), ("3", "^--")):
                if order == "3" and renewal != "poisson":
                    continue
                name = {"1": "first order", "2": "second order", "3": "quasi-static"}[order]
                top.plot(ratio, [float(x[f"dev{order}_sigma"]) for _, x in r], style, color=colors[n],
                         label=f"N = {n}, {name}")
                bottom.plot(ratio, [float(x[f"within2_{order}"]) for _, x in r], style, color=colors[n])
        top.axhline(4, color="grey", lw=0.8)
        top.axhline(2, color="grey", lw=0.8, ls="--")
        top.set_yscale("log")
        top.set_ylabel("worst |C_x - theory| / stderr, 0.02..36 rad/s")
        top.set_title(f"renewal = {renewal}, open chains (the ring runs: tools/validity_map.tsv)")
        bottom.axhline(0.85, color="grey", lw=0.8)
        bottom.set_ylabel("fraction of points within 2 stderr")
        bottom.set_xlabel("eps / eps_stall,  eps_stall = sqrt(2 / (3 N))")
    axes[0][0].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    map_table.save(fig, args.out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("slidespec")
    r.add_argument("table")
    r.add_argument("--precision", type=float, default=0.01)
    r.add_argument("--quick", action="store_true")
    p = sub.add_parser("plot")
    p.add_argument("table")
    p.add_argument("out")
    s = sub.add_parser("summary")
    s.add_argument("table")
    args = parser.parse_args()
    try:
        {"run": run, "plot": plot, "summary": summary}[args.command](args)
    except (OSError, ValueError, KeyError, subprocess.CalledProcessError) as error:
        print(f"validity_map: {error}", file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
