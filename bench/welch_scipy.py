"""scipy.signal.welch on the records of bench/welch_bench.cpp (random walks of 3900, 1e5 and 1e6
samples at 0.1 s, the same segment length, Hann, half overlap, segment means removed), and the
ratio to slidespec's welch_spectrum when given the benchmark's JSON:

    build/bench/slidespec_bench_welch --benchmark_out=/tmp/welch.json --benchmark_out_format=json
    /usr/bin/python3 bench/welch_scipy.py /tmp/welch.json
"""
import json
import sys
import timeit

import numpy as np
import scipy.signal


def fft_friendly(n):
    """The largest even length <= n with prime factors 2, 3, 5, 7 (welch_segment_samples)."""
    for m in range(n - n % 2, 1, -2):
        r = m
        for p in (2, 3, 5, 7):
            while r % p == 0:
                r //= p
        if r == 1:
            return m
    return 2


def main():
    cpp = {}
    if len(sys.argv) > 1:
        with open(sys.argv[1]) as f:
            for row in json.load(f)["benchmarks"]:
                name = row["name"]
                if name.startswith("BM_WelchSpectrum/") and row.get("aggregate_name", "median") == "median":
                    cpp[int(name.split("/")[1].split("_")[0])] = row["real_time"]  # [us]
    print(f"{'samples':>9} {'segment':>8} {'scipy [us]':>11} {'slidespec [us]':>15} {'scipy / slidespec':>18}")
    for samples in (3900, 100_000, 1_000_000):
        x = np.cumsum(np.random.default_rng(1).normal(size=samples))
        # slidespec transforms the first differences: same length, same work.
        segment = fft_friendly(2 * (samples - 1) // 9)
        call = lambda: scipy.signal.welch(x, fs=10.0, window="hann", nperseg=segment, noverlap=segment // 2,
                                          detrend="constant", return_onesided=True, scaling="density")
        number = max(1, int(0.2 / max(timeit.timeit(call, number=1), 1e-6)))
        seconds = min(timeit.repeat(call, number=number, repeat=5)) / number
        ours = cpp.get(samples)
        ratio = f"{seconds * 1e6 / ours:18.2f}" if ours else f"{'-':>18}"
        print(f"{samples:>9} {segment:>8} {seconds * 1e6:11.1f} {ours or float('nan'):15.1f} {ratio}")


if __name__ == "__main__":
    main()
