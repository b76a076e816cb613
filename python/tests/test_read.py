"""ss.read of a run's PREFIX.tsv and PREFIX.json: the same Result, numbers as numbers under the
JSON's keys (run through ctest: SLIDESPEC names the executable)."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import slidespec as ss

CLI = os.environ.get("SLIDESPEC", "slidespec")
# What only the JSON holds: the run's record of its machine and work, and its full request.
ONLY_IN_JSON = {"wall_seconds", "realization_steps", "miniblock_steps", "throughput_miniblock_steps_per_second",
                "simd_path", "threads"}


@pytest.fixture(scope="module", params=["constant force", "spring"])
def run(request, tmp_path_factory):
    out = tmp_path_factory.mktemp("read") / "run"
    spring = ["--set", "drive=spring", "--set", "k_drive=1e4"] if request.param == "spring" else []
    done = subprocess.run([CLI, "run", "--case", "reference", "--set", "N=12", *spring, "--omega-min", "1",
                           "--omega-max", "100", "--precision", "0.2", "--seed", "1", "--threads", "2",
                           "--out", str(out), "--no-plot", "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return ss.read(f"{out}.tsv"), ss.read(f"{out}.json"), request.param == "spring"


def test_the_tsv_reads_as_the_json_does(run):
    table, exact, _ = run
    got, expected = table.to_dict(), exact.to_dict()
    assert set(got) == set(expected) - ONLY_IN_JSON
    for key, value in got.items():
        if key == "points":
            assert len(value) == len(expected[key])
            for point, other in zip(value, expected[key]):
                assert point == {name: v for name, v in other.items() if name != "bins"}
        elif key == "sub_bands":
            assert value == [{name: v for name, v in band.items() if name != "rounds"} for band in expected[key]]
        elif key == "request":
            assert value == {"seed": 1, "precision": 0.2, "control_variate": "shadow"}
            assert value.items() <= expected[key].items()
        else:
            assert value == expected[key], key
            assert type(value) is type(expected[key]), key


def test_parameters_and_landmarks_are_numbers_under_the_jsons_keys(run):
    table, exact, spring = run
    assert table.to_dict()["parameters"] == exact.to_dict()["parameters"]
    assert table.parameters == exact.parameters
    assert table.parameters["N"] == 12 and table.parameters["v"] == 5e-4
    assert table.landmarks == exact.landmarks
    assert [type(value) for value in table.landmarks.values()] == [type(value) for value in exact.landmarks.values()]
    landmarks = {"renewal_rate", "omega_c", "diffusion_D", "eq1_prefactor", "coupling_eps", "forces_can_stall",
                 "stall_fraction"}
    if spring:
        landmarks |= {"omega_s", "omega_resonance", "d0", "C_x_zero"}
    assert set(table.landmarks) == landmarks
    assert table.landmarks["forces_can_stall"] is False
    assert table.landmarks["stall_fraction"] == 0.5  # alpha F_kin / (2 (F_drive - F_kin)) = 1 x 5 / 10
    p = ss.Parameters("reference", N=12, **({"drive": "spring", "k_drive": 1e4} if spring else {}))
    assert ss.Parameters(**table.parameters) == p
    assert table.seed == exact.seed == 1
    assert sorted(table.columns) == sorted(column for column in exact.columns if column != "bins")  # FFT bins
    for column in table.columns:
        a, b = getattr(table, column), getattr(exact, column)
        assert (a == b) if isinstance(a, list) else a.tobytes() == b.tobytes(), column
    assert math.isnan(table.theory2[0]) == spring


def test_a_table_cut_short_is_refused(tmp_path):
    """A run's table whose last rows are gone (a copy cut short) is not a shorter result."""
    out = tmp_path / "whole"
    done = subprocess.run([CLI, "run", "--omega-min", "1", "--omega-max", "100", "--precision", "0.2",
                           "--out", str(out), "--no-plot", "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = (tmp_path / "whole.tsv").read_text().splitlines(keepends=True)
    (tmp_path / "cut.tsv").write_text("".join(lines[:-5]))
    with pytest.raises(ValueError, match=r"12 point rows where its header counts 17: the table was cut short"):
        ss.read(tmp_path / "cut.tsv")


def test_a_sweep_whose_run_files_were_swapped_is_refused(tmp_path):
    """A sweep's combined table names each run: a run file replaced by another run's is found."""
    out = tmp_path / "sw"
    done = subprocess.run([CLI, "sweep", "alpha=1,0.6", "--omega-min", "1", "--omega-max", "10", "--precision",
                           "0.2", "--out", str(out), "--no-plot", "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert [r.label for r in ss.read(f"{out}.tsv")] == ["reference", "reference + alpha=0.6"]
    (tmp_path / "sw_alpha=1.tsv").write_bytes((tmp_path / "sw_alpha=0.6.tsv").read_bytes())
    for combined in ("sw.tsv", "sw.json"):
        with pytest.raises(ValueError, match=r"run_0 is 'reference', but .*sw_alpha=1.tsv holds 'reference \+ "
                                             r"alpha=0.6': the sweep's files no longer agree"):
            ss.read(tmp_path / combined)
