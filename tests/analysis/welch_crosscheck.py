"""slidespec analyze on a 3900-sample record (a random walk, omega^-2, plus a white floor) against
a textbook Welch estimate written here with numpy alone (Hann, 50% overlap, segment means removed,
no prewhitening) and against the exact spectrum. Run by ctest with SLIDESPEC set."""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

DT = 0.1  # [s]
N = 3900
STEP_SD = 0.2  # [um] random-walk step
FLOOR_SD = 0.3  # [um] white sensor noise
SPEED = 5.0  # [um/s] the slide the walk rides on: analyze removes its line, and a record at rest is no slide


def numpy_welch(x, length):
    """Two-sided C(omega_k), docs/model.md §3 normalisation, the bins of a segment of `length`."""
    hop = length // 2
    window = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(length) / length)
    count = (len(x) - length) // hop + 1
    total = np.zeros(length // 2 + 1)
    for s in range(count):
        segment = x[s * hop : s * hop + length]
        total += np.abs(np.fft.rfft(window * (segment - segment.mean()))) ** 2
    return total * DT / (2 * np.pi * np.sum(window**2) * count)


def exact(omega):
    """Random walk of step STEP_SD plus white FLOOR_SD, sampled every DT [um^2 s]."""
    walk = STEP_SD**2 * DT / (2 * np.pi * 4 * np.sin(omega * DT / 2) ** 2)
    return (walk + FLOOR_SD**2 * DT / (2 * np.pi)) * 1e-12  # [m^2 s]


def main():
    rng = np.random.default_rng(3900)
    x = np.cumsum(rng.normal(0, STEP_SD, N)) + rng.normal(0, FLOOR_SD, N)
    t = np.arange(N) * DT
    failures = []
    with tempfile.TemporaryDirectory() as work:
        record = os.path.join(work, "walk.csv")
        np.savetxt(record, np.column_stack([t, x + SPEED * t]), delimiter=",", header="t (s),x (um)", comments="")
        subprocess.run([os.environ["SLIDESPEC"], "analyze", record, "--no-plot", "--quiet", "--out",
                        os.path.join(work, "an")], check=True)
        with open(os.path.join(work, "an.json")) as f:
            doc = json.load(f)
    points = doc["points"]
    estimator = doc["estimator"]
    lowest_allowed = 1.5 * 10 * 2 * math.pi / (N * DT)
    print(f"estimator {estimator['name']}: {estimator['segments']} segments of {estimator['segment_samples']}")
    print(f"lowest point {points[0]['omega']:.4g} rad/s; 1.5 x 10 x 2 pi / T = {lowest_allowed:.4g}")
    if points[0]["omega"] > lowest_allowed:
        failures.append("the lowest point is above 1.5 x 10 x 2 pi / T")

    reference = numpy_welch(x * 1e-6, estimator["segment_samples"])
    spacing = 2 * math.pi / (estimator["segment_samples"] * DT)
    agree_welch = agree_exact = 0
    for p in points:
        bins = range(p["first_bin"], p["first_bin"] + p["bins"])
        textbook = np.mean([reference[k] for k in bins])
        truth = np.mean([exact(k * spacing) for k in bins])
        agree_welch += p["C_low"] <= textbook <= p["C_high"]
        agree_exact += p["C_low"] <= truth <= p["C_high"]
    share_welch, share_exact = agree_welch / len(points), agree_exact / len(points)
    print(f"{len(points)} points; numpy Welch inside the error bars: {share_welch:.3f}, the exact: {share_exact:.3f}")
    if share_welch < 0.85:
        failures.append(f"only {share_welch:.2f} of the points agree with the numpy Welch estimate")
    if share_exact < 0.85:
        failures.append(f"only {share_exact:.2f} of the points agree with the exact spectrum")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
