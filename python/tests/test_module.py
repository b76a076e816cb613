"""The Python module against the command line it must agree with (run through ctest:
PYTHONPATH holds the built package, SLIDESPEC the executable)."""

import json
import pathlib
import os
import pickle
import signal
import struct
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import slidespec as ss
from slidespec import _core

CLI = os.environ.get("SLIDESPEC", "slidespec")
COLUMNS = ["omega", "C_x", "stderr", "theory", "theory_at_omega", "n_avg", "bandwidth", "theory2"]


def cli(*args, check=True):
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done


def same_bits(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


# A short run: three sub-bands, a few rounds each, about a second.
OVERRIDES = {"alpha": 0.4, "N": 12}
BAND = {"omega_min": 1, "omega_max": 1e3, "precision": 0.08, "seed": 3}


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "short"
    cli("run", "--case", "reference", "--set", "alpha=0.4", "--set", "N=12", "--omega-min", "1",
        "--omega-max", "1e3", "--precision", "0.08", "--seed", "3", "--threads", "2",
        "--out", str(out), "--no-plot", "--quiet")
    return out


@pytest.fixture(scope="module")
def py_run():
    return ss.run(ss.Parameters("reference", **OVERRIDES), threads=1, **BAND)


def test_run_is_bitwise_the_command_line(cli_run, py_run):
    with open(f"{cli_run}.json") as f:
        expected = json.load(f)
    got = py_run.to_dict()
    assert len(py_run) == len(expected["points"]) == 25
    for column in COLUMNS:
        assert same_bits(getattr(py_run, column), [p[column] for p in expected["points"]]), column
    for key in ("complete", "reached_precision", "measured_mean_speed", "simulated_time", "sub_bands",
                "parameters", "request", "landmarks", "realization_steps", "label"):
        assert got[key] == expected[key], key
    assert py_run.complete and py_run.mean_speed == expected["measured_mean_speed"]["value"]


# What a run's PREFIX.json says of the machine and the threads that ran it, not of the run.
MACHINE_FIELDS = {"wall_seconds", "throughput_miniblock_steps_per_second", "threads", "simd_path"}


def bits(value):
    """A document with each float as its 8 bytes: equal only where every bit is (and an int
    is not a float)."""
    if isinstance(value, dict):
        return {key: bits(v) for key, v in value.items()}
    if isinstance(value, list):
        return [bits(v) for v in value]
    return ("float", struct.pack("<d", value)) if isinstance(value, float) else value


@pytest.mark.parametrize("keys", [{}, {"drive": "spring", "k_drive": 1e4}])
def test_a_run_is_the_command_lines_json_to_the_last_bit(keys, tmp_path):
    # The binding converts the run's doubles, not the JSON text: every number, field and
    # point must still be what PREFIX.json holds (which prints each double exactly).
    out = tmp_path / "run"
    overrides = [arg for key, value in keys.items() for arg in ("--set", f"{key}={value}")]
    cli("run", "--case", "reference", "--set", "N=12", *overrides, "--omega-min", "10", "--omega-max", "1e3",
        "--realizations", "8", "--seed", "5", "--threads", "2", "--out", str(out), "--no-plot", "--quiet")
    with open(f"{out}.json") as f:
        expected = json.load(f)
    got = ss.run(ss.Parameters("reference", N=12, **keys), omega_min=10, omega_max=1e3, realizations=8, seed=5,
                 threads=1).to_dict()
    assert list(got) == list(expected)
    for key in set(expected) - MACHINE_FIELDS:
        assert bits(got[key]) == bits(expected[key]), key
    assert ("C_F_spring" in got["points"][0]) == bool(keys)


def test_the_parameter_table_gives_the_figures_symbols():
    symbols = {row["key"]: row["symbol"] for row in ss.parameter_table()}
    assert symbols["eta0"] == "*η*_{0}" and symbols["k_drive"] == "*k*_{drive}" and symbols["N"] == "N"
    # plot_spectra.py, which runs without this module, reads the same symbols from its file.
    written = pathlib.Path(__file__).resolve().parents[2] / "tools" / "parameter_symbols.tsv"
    assert dict(line.split("\t") for line in written.read_text().splitlines() if not line.startswith("#")) == symbols


def test_read_gives_the_same_result(cli_run, py_run):
    exact = ss.read(f"{cli_run}.json")
    table = ss.read(f"{cli_run}.tsv")
    for column in ("omega", "C_x", "stderr", "theory", "theory2"):
        # Both print each number in the shortest form that reads back as the same double.
        assert same_bits(getattr(exact, column), getattr(py_run, column))
        assert same_bits(getattr(table, column), getattr(py_run, column))
    assert table.complete is True and exact.complete is True
    assert table.parameters == py_run.parameters
    # Prose with " = " in it (the "# columns:" line) is not read as a KEY = VALUE line.
    assert not [key for key in table.to_dict() if not key.isidentifier()]
    assert table.seed == 3 and table.case == "reference"
    assert abs(table.mean_speed / py_run.mean_speed - 1) < 1e-9
    assert [b["realizations"] for b in table.sub_bands] == [b["realizations"] for b in py_run.sub_bands]
    # The same table with a '#'-prefixed column line reads alike.
    with open(f"{cli_run}.tsv") as f:
        lines = f.read().splitlines()
    column_line = next(i for i, line in enumerate(lines) if line.lstrip("# ").startswith("omega\t"))
    lines[column_line] = lines[column_line].lstrip("# ")  # the plain column line
    hashed = cli_run.parent / "hashed.tsv"
    hashed.write_text("\n".join(lines) + "\n")
    again = ss.read(hashed)
    assert again.columns == table.columns
    for column in table.columns:
        a, b = getattr(again, column), getattr(table, column)
        assert a == b if isinstance(a, list) else same_bits(a, b), column


def test_theory_is_the_command_line():
    printed = cli("theory", "--case", "short-renewal", "--set", "alpha=0.4", "--set", "k1=37.5").stdout
    rows = [line.split("\t") for line in printed.splitlines() if line and not line.startswith(("#", "omega"))]
    p = ss.Parameters("short-renewal", alpha=0.4, k1=37.5)
    omega = ss.omegas(0.1, 1e5, 8)
    values = ss.theory(p, omega)
    assert len(rows) == len(omega) == 49
    # The command prints every digit: the values are bitwise the same.
    assert same_bits([float(r[0]) for r in rows], omega)
    assert same_bits([float(r[1]) for r in rows], values)
    assert same_bits([float(r[2]) for r in rows], ss.eq1(p, omega))
    # The same values one at a time, for a scalar, and for an array's shape.
    assert ss.theory(p, float(omega[10])) == values[10]
    assert ss.theory(p, omega.reshape(7, 7)).shape == (7, 7)
    # Exact wherever the numbers fit in a double, refused below with the lowest omega.
    d = 5.0**2 * 1e-3 * 5e-4 / (12 * 30 * (10.0 - 5.0) ** 2)  # alpha^2 F_kin^2 a v / (12 N (F_drive - F_kin)^2)
    assert ss.theory("reference", 1e-14) == pytest.approx(d / (np.pi * 1e-28), rel=1e-12)
    with pytest.raises(ValueError, match="below 2.81e-80 rad/s"):
        ss.theory("reference", [1.0, 1e-300])
    with pytest.raises(ValueError, match="below 2.81e-80 rad/s"):
        ss.eq1("reference", 1e-100)


def test_second_order_theory_is_the_command_line():
    printed = cli("theory", "--set", "alpha=1.5", "--order", "2").stdout
    rows = [line.split("\t") for line in printed.splitlines() if line and not line.startswith(("#", "omega"))]
    p = ss.Parameters("reference", alpha=1.5)
    assert same_bits([float(r[3]) for r in rows], ss.theory(p, ss.omegas(), order=2))
    with pytest.raises(ValueError, match="eps"):
        ss.theory(ss.Parameters(renewal="periodic", alpha=4), 1.0, order=2)
    with pytest.raises(ValueError, match="order"):
        ss.theory(p, 1.0, order=3)


def test_spring_drive_theory_and_run_carry_the_force_spectrum():
    p = ss.Parameters("reference", N=12, chain="ring", alpha=0.5, drive="spring", k_drive=1e4)
    assert p["drive"] == "spring" and p["k_drive"] == 1e4
    printed = cli("theory", "--set", "N=12", "--set", "chain=ring", "--set", "alpha=0.5", "--set", "drive=spring",
                  "--set", "k_drive=1e4").stdout
    rows = [line.split("\t") for line in printed.splitlines() if line and not line.startswith(("#", "omega"))]
    omega = ss.omegas()
    assert same_bits([float(r[1]) for r in rows], ss.theory(p, omega))
    assert same_bits([float(r[3]) for r in rows], ss.spring_force_theory(p, omega))
    landmarks = p.landmarks
    assert landmarks["omega_s"] == 1e4 * p["v"] / (p["F_drive"] - p["F_kin"])
    assert landmarks["diffusion_D"] == 0 and landmarks["C_x_zero"] > 0
    r = ss.run(p, omega_min=10, omega_max=100, realizations=4, seed=2)
    assert same_bits(r.C_F_spring, 1e4 ** 2 * r.C_x)
    assert same_bits(r.C_F_spring_theory, 1e4 ** 2 * r.theory)
    with pytest.raises(ValueError, match="k_drive"):
        ss.Parameters(drive="spring")
    with pytest.raises(ValueError, match="k_drive"):
        ss.Parameters(k_drive=1e4)
    with pytest.raises(ValueError, match="drive spring"):
        ss.spring_force_theory(ss.Parameters(), 1.0)
    with pytest.raises(ValueError, match="drive=spring"):
        ss.theory(p, 1.0, order=2)


def test_parameter_table_gives_every_key_with_its_unit_and_type():
    table = ss.parameter_table()
    keys = [row["key"] for row in table]
    assert keys + [row["key"] + "_l" for row in table if row["per_level"]] == _core.parameter_keys()
    units = {row["key"]: row["unit"] for row in table}
    assert units["M"] == "kg" and units["k0"] == "N/m" and units["v"] == "m/s" and units["alpha"] == ""
    # Each value comes back typed by its row's kind, including per-level keys of a tree.
    values = ss.Parameters("hierarchical").to_dict()
    kinds = {"count": int, "real": float, "word": str, "levels": str}
    for key, value in values.items():
        row = next(r for r in table if key in (r["key"], r["key"] + "_2"))
        assert isinstance(value, kinds[row["kind"]]), (key, value)
        if row["kind"] == "word":
            assert value in row["words"]
    assert "M: big block mass [kg]" in ss.Parameters.__doc__


@pytest.mark.parametrize("overrides", [{"alpha": -1}, {"nonsense": 3}, {"N": 2.5}, {"chain": "loop"},
                                       {"F_kin": 20}, {"v": 1e-3, "eta1": 5}])
def test_bad_parameters_raise_the_command_lines_message(overrides):
    with pytest.raises(ValueError) as error:
        ss.Parameters("reference", **overrides)
    args = [arg for key, value in overrides.items() for arg in ("--set", f"{key}={value}")]
    done = cli("theory", *args, check=False)
    assert done.returncode == 2
    assert done.stderr.strip() == f"slidespec: error: {error.value}"
    assert next(iter(overrides)) in str(error.value)


def test_bad_requests_and_files():
    with pytest.raises(ValueError, match="unknown case 'nope'"):
        ss.Parameters("nope")
    with pytest.raises(ValueError, match="precision"):
        ss.run("reference", precision=2)
    with pytest.raises(ValueError, match="omega"):
        ss.run("reference", omega_min=10, omega_max=1)
    with pytest.raises(ValueError, match="simd"):
        ss.run("reference", omega_min=100, omega_max=1e3, realizations=8, simd="sse9")
    with pytest.raises(ValueError, match="omega"):
        ss.theory("reference", [1.0, -2.0])
    with pytest.raises(OSError):
        ss.read("/nonexistent/reference.tsv")
    with pytest.raises(KeyError, match="alpha_9"):
        ss.Parameters()["alpha_9"]


def test_results_and_parameters_pickle_and_serialise(py_run):
    again = pickle.loads(pickle.dumps(py_run))
    for column in COLUMNS:
        assert same_bits(getattr(again, column), getattr(py_run, column))
    assert again.to_dict() == py_run.to_dict()
    assert json.loads(json.dumps(py_run.to_dict())) == py_run.to_dict()
    assert all(type(getattr(py_run, c)) is np.ndarray for c in COLUMNS)
    p = ss.Parameters("hierarchical", alpha_2=0.5, touching=[1, 2])
    q = pickle.loads(pickle.dumps(p))
    assert q == p and q.to_dict() == p.to_dict() and q["alpha_2"] == 0.5 and q["N_2"] == 10
    json.dumps(p.to_dict())
    assert ss.Parameters.from_dict(py_run.parameters) == ss.Parameters("reference", **OVERRIDES)
    assert p.replace(alpha_2=0.25)["alpha_2"] == 0.25


def test_progress_reaches_the_callers_thread_only():
    calls = []
    # Over a second on two cores, so that several waits of 0.1 s report progress on any machine.
    ss.run("reference", omega_min=0.01, omega_max=1e3, precision=0.1, threads=2,
           progress=lambda fraction, what: calls.append((threading.get_ident(), fraction, what)))
    assert len(calls) >= 2
    assert {ident for ident, _, _ in calls} == {threading.get_ident()}
    assert all(0 <= f <= 1 for _, f, _ in calls) and calls[-1][1] == 1.0
    assert any(what.startswith("sub-band") for _, _, what in calls)


def test_progress_bar(capsys):
    ss.run("reference", omega_min=10, omega_max=1e3, precision=0.2, threads=2, progress=True)
    assert "100.0%" in capsys.readouterr().err


def test_a_run_releases_the_gil():
    ticks, done = 0, threading.Event()
    worker = threading.Thread(target=lambda: (ss.run("reference", omega_min=1, omega_max=1e4,
                                                     precision=0.05, threads=1), done.set()))
    start = time.monotonic()
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Held, the GIL would let this thread tick once per 0.1 s wait at most; released, it
    # ticks every millisecond or so (a tenth of that leaves room for a busy machine).
    assert ticks > 0.1 * (time.monotonic() - start) / 0.001


CHILD = textwrap.dedent("""
    import pickle, sys, time, slidespec as ss
    started = []
    def progress(fraction, what):
        if fraction > 0.2 and not started:
            started.append(time.monotonic())
            print("running", flush=True)
    try:
        ss.run("reference", precision=PRECISION, seed=7, threads=2, progress=progress)
        print("finished", flush=True)
    except KeyboardInterrupt as e:
        pickle.dump(e.result, sys.stdout.buffer)
        sys.stdout.buffer.flush()
        if RESUME:
            pickle.dump(ss.resume(e.result, threads=1), open(sys.argv[1], "wb"))
""")


def interrupted_child(precision, resume, path):
    code = CHILD.replace("PRECISION", repr(precision)).replace("RESUME", repr(resume))
    child = subprocess.Popen([sys.executable, "-c", code, str(path)], stdout=subprocess.PIPE)
    assert child.stdout.readline() == b"running\n"
    signalled = time.monotonic()
    child.send_signal(signal.SIGINT)
    partial = pickle.load(child.stdout)
    stopped = time.monotonic() - signalled
    assert child.wait(timeout=300) == 0
    return partial, stopped


def test_ctrl_c_raises_promptly_with_the_partial_result(tmp_path):
    # At 0.5% the whole run takes ~10 s; it stops at the next block of steps.
    partial, stopped = interrupted_child(0.005, False, tmp_path / "unused")
    assert stopped < 2.0
    assert isinstance(partial, ss.Result) and not partial.complete
    assert len(partial) > 0 and partial.state is not None
    assert sum(b["realizations"] for b in partial.sub_bands) > 0


def test_an_interrupted_run_resumes_to_the_unbroken_numbers(tmp_path):
    # At 0.5% (~1.5 s on two cores) the interrupt lands well before the end.
    partial, _ = interrupted_child(0.005, True, tmp_path / "resumed.pickle")
    assert not partial.complete
    with open(tmp_path / "resumed.pickle", "rb") as f:
        resumed = pickle.load(f)
    out = tmp_path / "whole"
    cli("run", "--case", "reference", "--precision", "0.005", "--seed", "7", "--out", str(out), "--no-plot",
        "--quiet")
    whole = ss.read(f"{out}.json")
    assert resumed.complete and len(resumed) == len(whole) == 49
    for column in COLUMNS:
        assert same_bits(getattr(resumed, column), getattr(whole, column)), column


def test_analyze_is_the_command_line(tmp_path):
    record = tmp_path / "record"
    cli("synth", "--set", "alpha=0.4", "--duration", "1000", "--seed", "4", "--out", str(record))
    cli("analyze", f"{record}.csv", "--units", "um", "--resolution", "0.5e-6m", "--sensor-noise", "0.25e-6m",
        "--fit-slope", "3", "18", "--compare-case", "reference", "--fit", "alpha", "--out",
        str(tmp_path / "analysis"), "--no-plot", "--quiet")
    with open(tmp_path / "analysis.json") as f:
        expected = json.load(f)
    t, x = _read_csv(f"{record}.csv")
    a = ss.analyze(t, x, units="um", resolution=0.5e-6, sensor_noise=0.25e-6, fit_slope=(3, 18),
                   compare=ss.Parameters("reference"), fit="alpha")
    got = a.to_dict()
    assert [{k: v for k, v in p.items() if k not in ("fit", "residual")} for p in bits(got["points"])] == \
        bits(expected["points"])
    for key in ("slope_fit", "alpha_fit", "usable_band", "estimator", "segments", "model_parameters"):
        assert bits(got[key]) == bits(expected[key]), key
    for column in ("omega", "C_x", "stderr", "floor", "theory"):
        assert same_bits(getattr(a, column), [p[column] for p in expected["points"]]), column
    assert a.slope_fit["slope"] == expected["slope_fit"]["slope"]
    assert a.alpha == expected["alpha_fit"]["alpha"]
    assert a.mean_speed == expected["measured_mean_speed"]["value"]
    json.dumps(a.to_dict())
    assert pickle.loads(pickle.dumps(a)).alpha == a.alpha
    # The Python synth is the command line's (the CSV holds x in um, to its digits).
    ts, xs = ss.synth(ss.Parameters("reference", alpha=0.4), duration=1000, seed=4)
    np.testing.assert_allclose(xs, x * 1e-6, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(ts, t, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("flags, keywords", [
    (["--program", "1:20,0:5,3:20"], {"program": [(1, 20), (0, 5), (3, 20)]}),
    (["--strokes", "3", "--stroke-length", "5cm", "--dwell", "1"], {"strokes": 3, "stroke_length": 0.05, "dwell": 1}),
])
def test_synths_drives_and_load_point_are_the_command_lines(tmp_path, flags, keywords):
    record = tmp_path / "rig"
    cli("synth", "--case", "fast", "--set", "alpha=0.4", "--set", "drive=spring", "--set", "k_drive=1000",
        "--load-point", *flags, "--sample-interval", "0.01", "--seed", "5", "--out", str(record))
    t, x, force = _read_csv(f"{record}.csv")
    rig = ss.Parameters("fast", alpha=0.4, drive="spring", k_drive=1000)
    ts, xs, forces = ss.synth(rig, sample_interval=0.01, seed=5, load_point=True, **keywords)
    np.testing.assert_allclose(ts, t, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(xs, x * 1e-6, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(forces, force, rtol=1e-11)
    assert np.ptp(xs) > 0 and np.std(forces) > 0


@pytest.mark.parametrize("keywords, word", [
    ({"program": [(1, 1)], "strokes": 2, "stroke_length": 1.0}, "program: not with strokes"),
    ({"program": [(1, 1)], "duration": 5.0}, "program: sets the record's length"),
    ({"program": [(1, 0)]}, "program: each stretch"),
    ({"dwell": 1.0}, "dwell: only with strokes"),
    ({"strokes": 0, "stroke_length": 1.0}, "strokes: must be a whole number"),
    ({"load_point": True, "duration": 1.0}, "load_point: a load point pulls the slider only through a spring"),
])
def test_synths_drive_is_refused_naming_the_keyword(keywords, word):
    with pytest.raises(ValueError, match=word):
        ss.synth("fast", sample_interval=0.01, **keywords)


def _read_csv(path):
    rows = [line.split(",") for line in open(path) if line.strip() and not line.startswith("#")]
    return np.array([[float(v) for v in row] for row in rows[1:]]).T


def test_precision_excludes_duration_as_on_the_command_line():
    with pytest.raises(ValueError, match="precision excludes duration"):
        ss.run("reference", omega_min=1, omega_max=10, precision=0.1, duration=10)


@pytest.mark.parametrize("kwargs, error, word", [
    ({"seed": 1.5}, TypeError, "seed"),
    ({"seed": "1"}, TypeError, "seed"),
    ({"seed": True}, TypeError, "seed"),
    ({"seed": 2**64}, ValueError, "18446744073709551615"),
    ({"seed": -1}, ValueError, "seed"),
    ({"threads": 1.5}, TypeError, "threads"),
    ({"points": 8.0}, TypeError, "points"),
    ({"realizations": 2.5}, TypeError, "realizations"),
    ({"realizations": 0}, ValueError, "realizations"),
    ({"realizations": 8, "precision": 0.1}, ValueError, "precision excludes realizations"),
    ({"duration": 0}, ValueError, "duration"),
    ({"omega_min": "1"}, TypeError, "omega_min"),
])
def test_run_checks_types_as_the_command_line(kwargs, error, word):
    request = {"omega_min": 100, "omega_max": 1000, **kwargs}
    with pytest.raises(error, match=word):
        ss.run("reference", **request)


@pytest.mark.parametrize("call, error, word", [
    (lambda: ss.analyze(None, RECORD, dt=0.01, points=2.5), TypeError, "points"),
    (lambda: ss.analyze(None, RECORD, dt="0.01"), TypeError, "dt"),
    (lambda: ss.analyze(None, RECORD, dt=0.01, units=1), TypeError, "units"),
    (lambda: ss.analyze(None, RECORD, dt=0.01, omega_min="1"), TypeError, "omega_min"),
    (lambda: ss.analyze(None, RECORD, dt=0.01, theory_order=1.0), TypeError, "theory_order"),
    (lambda: ss.omegas(1, 10, points=2.5), TypeError, "points"),
    (lambda: ss.omegas("1", 10), TypeError, "omega_min"),
    (lambda: ss.theory("reference", "1"), TypeError, "omega"),
    (lambda: ss.theory("reference", [1, "2"]), TypeError, "omega"),
    (lambda: ss.theory("reference", 1, order=1.5), TypeError, "order"),
    (lambda: ss.synth(duration="5"), TypeError, "duration"),
    (lambda: ss.synth(seed=-1, duration=1.0), ValueError, "seed"),
])
def test_analyze_theory_and_omegas_check_types_as_the_command_line(call, error, word):
    with pytest.raises(error, match=word):
        call()


RECORD = [0.0, 1.0, 2.0] * 100


def test_read_of_a_sweep_gives_each_runs_result(tmp_path):
    out = tmp_path / "sw"
    cli("sweep", "alpha=0.5,1", "--omega-min", "1", "--omega-max", "10", "--precision", "0.2",
        "--out", str(out), "--no-plot", "--quiet")
    for suffix in (".tsv", ".json"):
        runs = ss.read(f"{out}{suffix}")
        assert [r.parameters["alpha"] for r in runs] == [0.5, 1.0]
        alone = ss.read(tmp_path / "sw_alpha=0.5.json")
        assert same_bits(runs[0].C_x, alone.C_x)
    (tmp_path / "sw_alpha=1.tsv").unlink()
    with pytest.raises(OSError):
        ss.read(f"{out}.tsv")


def test_read_refuses_what_is_not_a_table_file_with_oserror(tmp_path):
    for path in ("/dev/zero", "/dev/urandom", str(tmp_path), str(tmp_path / "none.tsv")):
        with pytest.raises(OSError):
            ss.read(path)
    huge = tmp_path / "huge.tsv"
    with open(huge, "wb") as f:  # sparse: no disk used
        f.truncate((1 << 30) + 1)
    with pytest.raises(OSError, match="more than"):
        ss.read(huge)
    binary = tmp_path / "binary.tsv"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(ValueError, match="UTF-8"):
        ss.read(binary)


def test_synth_checks_types_as_the_command_line():
    with pytest.raises(TypeError, match="seed"):
        ss.synth(seed=2.5, duration=1.0)


def test_bad_records():
    with pytest.raises(ValueError, match="gap"):
        ss.analyze([0, 1, 2, 4, 5], [0.0, 1, 2, 3, 4])
    with pytest.raises(ValueError, match="units"):
        ss.analyze(None, [0.0, 1.0], dt=1, units="furlong")
    with pytest.raises(ValueError, match="compare"):
        ss.analyze(None, np.arange(1000.0), dt=1, fit="alpha")


def test_help_names_units():
    for function in (ss.run, ss.theory, ss.analyze, ss.read, ss.synth, ss.omegas):
        assert "[" in function.__doc__ and "]" in function.__doc__, function.__name__
    assert "rad/s" in ss.run.__doc__ and "m^2 s" in ss.theory.__doc__


def test_landmarks_name_the_best_theory_that_holds():
    assert ss.Parameters("reference").landmarks["theory_kind"] == "second_order"
    outside = ss.Parameters("reference", N=2, alpha=1.04).landmarks  # eps 0.3, 0.52 of the stall
    assert outside["theory_kind"] == "none"
    assert "second order holds to eps 0.15" in outside["theory_kind_note"]
    assert outside["outside_first_order"]
    # Through a stiff spring the first order holds to 0.95 of the stall: the same eps is inside.
    stiff = ss.Parameters("reference", N=2, alpha=1.04, drive="spring", k_drive=1e5).landmarks
    assert stiff["theory_kind"] == "first_order" and not stiff["outside_first_order"]
    soft = ss.Parameters("reference", N=2, alpha=1.04, drive="spring", k_drive=1e2).landmarks
    assert soft["theory_kind"] == "none" and soft["outside_first_order"]


def test_runs_outside_the_first_order_theory_warn_as_the_command_line_does():
    p = ss.Parameters("reference", alpha=5)
    assert p.landmarks["forces_can_stall"]
    with pytest.warns(ss.ModelWarning, match="stall"):
        r = ss.run(p, omega_min=100, omega_max=1e3, realizations=8, threads=2)
    assert r.complete
    assert r.theory_kind == "none"


def test_analyze_takes_the_command_lines_window_and_resampling():
    data = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "realdata"
    table = np.loadtxt(data / "velstep3_TR2_exp013_sepiolite.txt", skiprows=1)
    before = ss.analyze(table[:, 0], table[:, 1], units="um", window=(20100, 21290))
    after = ss.analyze(table[:, 0], table[:, 1], units="um", window=(21350, 22319))
    assert before.mean_speed == pytest.approx(2e-7, rel=0.05)
    assert after.mean_speed == pytest.approx(2e-6, rel=0.05)
    assert any("linear interpolation" in note for note in before._data["notes"])
    assert before._data["estimator"]["name"] == "welch"
    with pytest.raises(ValueError, match="not uniform"):
        ss.analyze(table[:, 0], table[:, 1], units="um", resample="off")


def test_ctrl_c_interrupts_a_long_theory():
    # 3e6 omegas take about 30 s; Ctrl-C is heard between chunks of a tenth of a second.
    omega = np.geomspace(0.1, 1e5, 3_000_000)
    signalled = []
    timer = threading.Timer(0.3, lambda: (signalled.append(time.monotonic()), os.kill(os.getpid(), signal.SIGINT)))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        ss.theory("reference", omega)
    stopped = time.monotonic() - signalled[0]
    timer.join()
    assert stopped < 2.0


MEMORY_CHILD = textwrap.dedent("""
    import resource
    import slidespec as ss
    ss.synth(duration=10.0)  # everything loaded before the limit
    size = next(int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmSize:")) * 1024
    resource.setrlimit(resource.RLIMIT_AS, (size + 300_000_000, resource.RLIM_INFINITY))
    try:
        ss.synth(duration=9e4)  # 9e7 samples: 720 MB for x alone
    except MemoryError as e:
        print("MemoryError", e)
    t, x = ss.synth(duration=10.0)  # and the process goes on
    print("alive", x.size)
""")


def test_memory_exhaustion_raises_memory_error():
    done = subprocess.run([sys.executable, "-c", MEMORY_CHILD], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "MemoryError out of memory" in done.stdout, done.stdout
    assert "alive 10001" in done.stdout, done.stdout
