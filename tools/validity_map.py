#!/usr/bin/env python3
"""The validity map of docs/model.md §7.4: where the first- and second-order spectra meet
the simulation.

Usage: validity_map.py run SLIDESPEC TABLE.tsv [--precision P] [--quick] [--spring] [--renewal KIND] [--omega-max W]
       validity_map.py plot TABLE.tsv OUT.png
       validity_map.py summary TABLE.tsv [--slidespec SLIDESPEC]

`run` simulates, with `SLIDESPEC run --precision P` (one thread, 0.02 .. 36 rad/s, 4 points
a decade), N in {2, 3, 4, 6, 12, 30}, eps from 0.05 (periodic renewal: 0.0125) to 0.95 of
the stall boundary
(eps_stall = sqrt(2 / (3 N)) with the reference forces), poisson and periodic renewal,
two samples of each point (open and ring chains; for N = 2 two open ones, chain "open2"),
and writes, per run and point range (below v/a, around it, the omega^-4 range, all), the
worst deviation of `theory` (first order), `theory2` (second order) and, for poisson
renewal, the quasi-static spectrum of docs/model.md §7.5 (the run's `theory` times the
ratio of tools/quasi_static.py) in standard errors and in per cent, and the fraction of
points within 2 standard errors. `theory2` is the run's where it offers one; for poisson
renewal beyond the run's eps limit it is the run's `theory` times the second- over
first-order ratio of `SLIDESPEC theory --order 2` (column theory2_source), which the map
needs to place that limit; both ratios are averaged over each point's FFT bins. `--quick` runs a reduced grid. Rows are appended as
each run ends and a finished (renewal, chain, N, eps) is not run again, so an interrupted
map resumes. `--spring` runs the drive=spring points of docs/model.md §9.1 instead (k_drive
putting omega_s at 0.2, 2 and 20 v/a; N = 2, 3, 6, 12; the first order only) into the same
columns, with `drive` and `k_drive` saying which. `plot` draws the table; `summary` prints it as the Markdown table of
docs/model.md §7.4 (over all points; open and ring runs pooled: the same process). Exit status 2 and one line on stderr for an unusable
input; the table and the image are written atomically.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import map_table  # noqa: E402  (beside this script)
import quasi_static  # noqa: E402
import slidespec_tsv  # noqa: E402  (beside this script)

COLUMNS = ("renewal", "chain", "N", "eps", "eps_stall", "range", "points", "dev1_sigma", "dev1_percent",
           "within2_1", "dev2_sigma", "dev2_percent", "within2_2", "theory2_source", "reached_precision",
           "stationary", "mean_speed_ratio", "dev3_sigma", "dev3_percent", "within2_3", "drive", "k_drive")
NS = (2, 3, 4, 6, 12, 30)
# The simulation lumps the chain (docs/numerics.md): open and ring ends give the same
# process, so the ring runs, with their own seed, are an independent second sample. N = 2 has
# no ring; its second sample is an open chain with a third seed (chain column "open2").
SEEDS = {"open": "27", "ring": "28", "open2": "29"}
EPS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55)
# The first order's zeros put periodic renewal's first-order limit below 0.05.
SMALL_EPS = {"poisson": (), "periodic": (0.0125, 0.025)}
DRIVE_EXCESS = 5.0  # F_drive - F_kin of the reference case [N]; F_kin is 5 N too
OMEGA_MIN, OMEGA_MAX, POINTS = 0.02, 36, 4
RATE = 0.5  # v/a [1/s], the reference case's
# Point ranges in units of the renewal rate v/a.
# With --omega-max beyond 100 rad/s the omega^-4 range ends at 200 v/a (100 rad/s, below every
# omega_c of the grid: 141 rad/s for N = 2) and "high" holds the rest: the resonance and the
# top sub-runs, whose short realizations need the stationary start (docs/run.md, "Warm-up").
RANGES = (("below", 0, 0.5), ("around", 0.5, 10), ("omega^-4", 10, 200), ("high", 200, math.inf),
          ("all", 0, math.inf))
# drive=spring: stiffnesses putting omega_s = k_drive v / (F_drive - F_kin) at 0.2, 2 and 20 v/a
# (0.1, 1 and 10 rad/s), inside the band; a few N and eps each, from small to 0.95 of the stall.
SPRING_K = (1e3, 1e4, 1e5)
RATE_PER_STIFFNESS = 0.001 / DRIVE_EXCESS  # omega_s / (v/a) = k_drive a / (F_drive - F_kin), a = 1 mm
SPRING_EPS = {2: (0.05, 0.3, 0.5485), 3: (0.05, 0.25, 0.4478), 6: (0.05, 0.15, 0.3167), 12: (0.1, 0.2239)}


def eps_stall(n):
    """The stall boundary alpha F_kin = 2 (F_drive - F_kin) in eps, for the reference forces."""
    return 2 / math.sqrt(6 * n)


def grid(quick, spring, renewals):
    """(renewal, chain, N, eps, k_drive) of each run; k_drive 0 is the constant force."""
    if spring:
        for chain in SEEDS:
            for renewal in renewals:
                for n, values in SPRING_EPS.items():
                    if (chain == "ring" and n < 3) or (chain == "open2" and n != 2):
                        continue
                    for eps in values:
                        for k in SPRING_K:
                            yield renewal, chain, n, (0.025 if renewal == "periodic" and eps == 0.05 else eps), k
        return
    ns = (3, 6, 30) if quick else NS
    for chain in ("open", "ring", "open2"):
        for renewal in renewals:
            for n in ns:
                if (chain == "ring" and n < 3) or (chain == "open2" and n != 2):
                    continue
                stall = eps_stall(n)
                values = [*SMALL_EPS[renewal], *(e for e in EPS if e < 0.92 * stall), round(0.95 * stall, 4)]
                for eps in values:
                    yield renewal, chain, n, eps, 0.0


def read_tsv(path):
    """Header values (`# key = value`) and the data columns of a slidespec TSV."""
    table = slidespec_tsv.read(path)
    return table.values, table.columns()


def case_sets(renewal, chain, n, eps, k_drive):
    """The --set options of a grid point (the reference case otherwise)."""
    alpha = eps * math.sqrt(6 * n)
    sets = ["--set", f"N={n}", "--set", f"alpha={alpha:.10g}", "--set", f"renewal={renewal}", "--set",
            f"chain={chain.rstrip('2')}"]
    if k_drive:
        sets += ["--set", "drive=spring", "--set", f"k_drive={k_drive:g}"]
    return sets


def reported_theory(slidespec, renewal, n, eps, k_drive):
    """The theory_kind the program reports at a grid point."""
    out = subprocess.run([slidespec, "theory", *case_sets(renewal, "open", n, eps, k_drive), "--omega", "1"],
                         check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        if line.startswith("# theory_kind = "):
            return line.split("=", 1)[1].split("#")[0].strip()
    raise ValueError(f"{slidespec} theory printed no theory_kind")


def simulate(slidespec, work, renewal, chain, n, eps, k_drive, precision, omega_max=OMEGA_MAX):
    sets = case_sets(renewal, chain, n, eps, k_drive)
    span = ["--omega-min", str(OMEGA_MIN), "--omega-max", str(omega_max), "--points", str(POINTS)]
    prefix = os.path.join(work, "run")
    subprocess.run(["nice", "-n", "10", slidespec, "run", *sets, *span, "--precision", str(precision), "--seed", SEEDS[chain],
                    "--threads", "1", "--out", prefix, "--no-plot", "--quiet"], check=False)
    if not os.path.exists(prefix + ".tsv"):
        raise ValueError(f"{renewal} {chain} N={n} eps={eps}: the run wrote no table")
    header, data = read_tsv(prefix + ".tsv")
    source = "run"
    if header.get("theory_kind") == "quasi_static":
        data["theory2"] = [math.nan] * len(data["theory2"])  # the run's theory2 is the quasi-static one
    data["theory3"] = [math.nan] * len(data["theory"])
    if renewal != "poisson" or k_drive:
        if all(math.isnan(x) for x in data["theory2"]):
            source = "none"
        return header, data, source
    # Poisson renewal under a constant force: the run's first order times a ratio averaged
    # over each point's FFT bins, weighted by the first order (as the run's theory is; around
    # v/a the ratio bends within the bins, and its value at the point's omega is up to 0.9%
    # off): the series' where the run gives no theory2 (theory2_source = ratio), and the
    # quasi-static spectrum's of tools/quasi_static.py below the stall (docs/model.md §7.5).
    with open(prefix + ".json") as f:
        bins = [p["bins"] for p in json.load(f)["points"]]
    omegas = [b["first"] + i * b["spacing"] for b in bins for i in range(b["count"])]
    with open(prefix + "_omegas", "w") as f:
        f.write("\n".join(repr(w) for w in omegas) + "\n")
    subprocess.run([slidespec, "theory", *sets, "--omega-file", prefix + "_omegas", "--order", "2", "--out",
                    prefix + "_theory"], check=True, stderr=subprocess.DEVNULL)
    _, theory = read_tsv(prefix + "_theory.tsv")
    first = theory["C_x"]

    def bin_averaged(ratio):
        out, start = [], 0
        for t, b in zip(data["theory"], bins):
            stop = start + b["count"]
            weight = sum(first[start:stop])
            out.append(t * sum(c * r for c, r in zip(first[start:stop], ratio[start:stop])) / weight)
            start = stop
        return out

    if all(math.isnan(x) for x in data["theory2"]):
        data["theory2"] = bin_averaged([c2 / c1 for c1, c2 in zip(first, theory["C_x2"])])
        source = "ratio"
    if eps < eps_stall(n):
        data["theory3"] = bin_averaged(list(quasi_static.QuasiStatic(n, eps).ratio([w / RATE for w in omegas])))
    return header, data, source


def deviations(values, data, keep):
    sigmas = [abs(c - t) / s for c, t, s, k in zip(data["C_x"], values, data["stderr"], keep) if k]
    percents = [100 * abs(c / t - 1) for c, t, k in zip(data["C_x"], values, keep) if k]
    if not sigmas or any(math.isnan(x) for x in sigmas):
        return math.nan, math.nan, math.nan
    return max(sigmas), max(percents), sum(x <= 2 for x in sigmas) / len(sigmas)


def rows_of(renewal, chain, n, eps, k_drive, header, data, source):
    out = []
    for name, low, high in RANGES:
        keep = [low <= w / RATE < high for w in data["omega"]]
        if name == "high" and not any(keep):
            continue  # a map to 36 rad/s: its rows stay as they were
        d1 = deviations(data["theory"], data, keep)
        d2 = deviations(data["theory2"], data, keep)
        d3 = deviations(data["theory3"], data, keep)
        speed = float(header["measured_mean_speed"]) / float(header["v"])
        out.append((renewal, chain, n, eps, round(eps_stall(n), 4), name, sum(keep), *d1[:2], d1[2], *d2[:2], d2[2],
                    source, float(header["reached_precision"]), header["stationary"], speed, *d3[:2], d3[2],
                    "spring" if k_drive else "force", k_drive))
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
            f = line.rstrip("\n").split("\t")
            done.add((f[0], f[1], int(f[2]), float(f[3]), float(f[21])))
    else:
        lines = ["\t".join(COLUMNS) + "\n"]
    with tempfile.TemporaryDirectory() as work:
        for renewal, chain, n, eps, k_drive in grid(args.quick, args.spring, args.renewal or ("poisson", "periodic")):
            if (renewal, chain, n, eps, k_drive) in done or args.chain not in (None, chain):
                continue
            header, data, source = simulate(args.slidespec, work, renewal, chain, n, eps, k_drive, args.precision,
                                            args.omega_max)
            lines += ["\t".join(fmt(x) for x in row) + "\n"
                      for row in rows_of(renewal, chain, n, eps, k_drive, header, data, source)]
            write_atomically(args.table, lines)
            print(f"{renewal} {chain} N={n} eps={eps} k_drive={k_drive:g}: done", file=sys.stderr, flush=True)


def write_atomically(path, lines):
    handle, temporary = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)))
    with os.fdopen(handle, "w") as f:
        f.writelines(lines)
    os.replace(temporary, path)


def read_table(path):
    return [dict(zip(COLUMNS, r)) for r in map_table.rows(path, COLUMNS, "validity_map")]


def pooled(runs, order):
    """Worst deviation (stderr, %) and share within 2 stderr over runs of one point; None if not computed."""
    sigma = max(float(r[f"dev{order}_sigma"]) for r in runs)
    if math.isnan(sigma):
        return None
    percent = max(float(r[f"dev{order}_percent"]) for r in runs)
    within = sum(float(r[f"within2_{order}"]) * int(r["points"]) for r in runs) / sum(int(r["points"]) for r in runs)
    return sigma, percent, within


def cell(result):
    sigma, percent, within = result
    return f"{sigma:.1f}, {percent:.1f}%; {100 * within:.0f}%"


def summary(args):
    """The constant force's table of docs/model.md §7.4, then the spring's of §9.1 (with
    --slidespec, the theory the program reports at each point and whether it holds there)."""
    rows = [r for r in read_table(args.table) if r["range"] == "all"]
    point = lambda r: (r["renewal"], int(r["N"]), float(r["eps"]), float(r["k_drive"]))  # noqa: E731
    keys = sorted({point(r) for r in rows}, key=lambda k: (k[0] != "poisson", k[1:]))
    print("| renewal | N | eps | eps / eps_stall | first order: worst (stderr, %); within 2 stderr |"
          " second order: worst (stderr, %); within 2 stderr | quasi-static (§7.5) |")
    print("|---|---|---|---|---|---|---|")
    for key in (k for k in keys if k[3] == 0):
        renewal, n, eps, _ = key
        runs = [r for r in rows if point(r) == key]
        cells = []
        for order in ("1", "2", "3"):
            result = pooled(runs, order)
            cells.append(cell(result) if result else
                         "not computed" if order != "3" or renewal == "poisson" else "not derived")
        print(f"| {renewal} | {n} | {eps:g} | {eps / eps_stall(n):.2f} | {cells[0]} | {cells[1]} | {cells[2]} |")
    print()
    print("| renewal | N | eps | eps / eps_stall | omega_s / (v/a) | first order: worst (stderr, %); within 2 stderr |"
          + (" reported | holds |" if args.slidespec else ""))
    print("|---|---|---|---|---|---|" + ("---|---|" if args.slidespec else ""))
    for key in (k for k in keys if k[3] > 0):
        renewal, n, eps, k_drive = key
        first = pooled([r for r in rows if point(r) == key], "1")
        line = (f"| {renewal} | {n} | {eps:g} | {eps / eps_stall(n):.2f} | {k_drive * RATE_PER_STIFFNESS:g} | "
                f"{cell(first)} |")
        if args.slidespec:
            kind = reported_theory(args.slidespec, renewal, n, eps, k_drive)
            holds = first[0] <= 4 and first[2] >= 0.85
            line += f" {kind} | {'yes' if holds else 'no'} |"
        print(line)


def plot(args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    every = [r for r in read_table(args.table) if r["chain"] == "open" and r["range"] == "all"]
    rows = [r for r in every if float(r["k_drive"]) == 0]
    fig, axes = plt.subplots(2, 3, figsize=(18, 8), sharex=True)
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
    # drive = spring: the first order only, by stiffness (omega_s in units of v/a).
    top, bottom = axes[0][2], axes[1][2]
    springs = [r for r in every if float(r["k_drive"]) > 0]
    for renewal, marker in (("poisson", "o"), ("periodic", "s")):
        for k, style in zip(SPRING_K, (":", "--", "-")):
            for n in SPRING_EPS:
                r = sorted((float(x["eps"]), x) for x in springs
                           if x["renewal"] == renewal and int(x["N"]) == n and float(x["k_drive"]) == k)
                if not r:
                    continue
                ratio = [e / eps_stall(n) for e, _ in r]
                fill = colors[n] if renewal == "poisson" else "none"
                label = f"{renewal}, omega_s = {k * RATE_PER_STIFFNESS:g} v/a" if n == 2 else None
                top.plot(ratio, [float(x["dev1_sigma"]) for _, x in r], marker + style, color=colors[n],
                         mfc=fill, label=label)
                bottom.plot(ratio, [float(x["within2_1"]) for _, x in r], marker + style, color=colors[n], mfc=fill)
    top.axhline(4, color="grey", lw=0.8)
    top.axhline(2, color="grey", lw=0.8, ls="--")
    top.set_yscale("log")
    top.set_title("drive = spring: first order (colours: N; open markers: periodic)")
    bottom.axhline(0.85, color="grey", lw=0.8)
    bottom.set_xlabel("eps / eps_stall,  eps_stall = sqrt(2 / (3 N))")
    top.legend(fontsize=6)
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
    r.add_argument("--omega-max", type=float, default=OMEGA_MAX,
                   help="top of the band [rad/s] (default 36; up to 1e5 adds the 'high' range)")
    r.add_argument("--spring", action="store_true", help="the drive=spring points instead of the constant force's")
    r.add_argument("--renewal", action="append", choices=("poisson", "periodic"), help="only this renewal kind")
    r.add_argument("--chain", choices=tuple(SEEDS), help="only this sample's runs (open2: N = 2's second)")
    p = sub.add_parser("plot")
    p.add_argument("table")
    p.add_argument("out")
    s = sub.add_parser("summary")
    s.add_argument("table")
    s.add_argument("--slidespec", help="the program, to name the theory it reports at each spring point")
    args = parser.parse_args()
    try:
        {"run": run, "plot": plot, "summary": summary}[args.command](args)
    except (OSError, ValueError, KeyError, subprocess.CalledProcessError) as error:
        print(f"validity_map: {error}", file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
