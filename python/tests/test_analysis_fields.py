"""ss.analyze's fields are the command line's PREFIX.json to the last bit: the binding builds
them from the library's report, not from the JSON, so every field, number and type is
compared with what `slidespec analyze` writes of the same record."""

import json
import subprocess
import warnings

import numpy as np

import slidespec as ss
from test_module import CLI, bits

def write_csv(path, columns):
    """The columns as CSV, each double in the shortest text that reads back as itself."""
    names = list(columns)
    rows = zip(*(columns[name] for name in names))
    path.write_text(",".join(names) + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))


def command_line_fields(tmp_path, columns, options):
    """PREFIX.json of `slidespec analyze` on the columns written as a file, without its points."""
    record = tmp_path / "record.csv"
    write_csv(record, columns)
    done = subprocess.run([CLI, "analyze", str(record), "--units", "m", *options, "--out", str(tmp_path / "a"),
                           "--no-plot", "--quiet"], capture_output=True, text=True)
    assert done.returncode in (0, 3), done.stderr
    document = json.loads((tmp_path / "a.json").read_text())
    del document["points"]
    assert document["record"].pop("file") == str(record)
    return document


# The options these records' texts name, as the command line and Python spell them: the
# library's words are the same, each front end names its own options.
SPELLINGS = {"--set ": "", "--compare-case": "compare", "--fit": "fit", "--machine-stiffness": "machine_stiffness",
             "--units": "units"}


def in_pythons_words(value):
    """The command line's document with each text as Python words it."""
    if isinstance(value, dict):
        return {key: in_pythons_words(v) for key, v in value.items()}
    if isinstance(value, list):
        return [in_pythons_words(v) for v in value]
    if isinstance(value, str):
        for command_line, python in SPELLINGS.items():
            value = value.replace(command_line, python)
    return value


def assert_same_fields(got, expected):
    assert list(got) == list(expected)
    expected = in_pythons_words(expected)
    for key in expected:
        assert bits(got[key]) == bits(expected[key]), key


def test_a_model_fit_is_the_command_lines_json_to_the_last_bit(tmp_path):
    t, x = ss.synth("reference", sample_interval=0.02, duration=400, resolution=0, sensor_noise=2e-9, seed=4)
    expected = command_line_fields(tmp_path, {"t": t, "x": x}, ["--compare-case", "reference", "--fit", "alpha,a"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a fit that fails is compared as well as one that holds
        got = ss.analyze(t, x, compare="reference", fit="alpha,a").to_dict()
    del got["points"]
    assert "model_fit" in got and len(got["model_fit"]["covariance"]) >= 2
    assert_same_fields(got, expected)


def test_strokes_are_the_command_lines_json_to_the_last_bit(tmp_path):
    synthesized = tmp_path / "strokes"
    done = subprocess.run([CLI, "synth", "--case", "fast", "--set", "alpha=0.4", "--strokes", "8",
                           "--stroke-length", "20mm", "--dwell", "1", "--sample-interval", "0.01",
                           "--resolution", "0", "--sensor-noise", "0.05um", "--seed", "2", "--out", str(synthesized)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    t, x = np.loadtxt(f"{synthesized}.csv", delimiter=",", comments="#", skiprows=_header_line(synthesized),
                      unpack=True, usecols=(0, 1))
    x *= 1e-6  # the file's um, in metres as the command line is told (--units m)
    expected = command_line_fields(tmp_path, {"t": t, "x": x}, ["--fit-slope", "3", "30"])
    got = ss.analyze(t, x, fit_slope=(3, 30)).to_dict()
    del got["points"]
    assert got["strokes"]["count"] >= 4 and "slope_fit" in got
    assert_same_fields(got, expected)


def rig_record():
    """A rig's record: t, the load point v t read with 5 nm of noise, and the friction mu of
    the spring's force over 10 MPa x 25 cm^2."""
    rig = ss.Parameters("reference", drive="spring", k_drive=1e8, v=3e-5, F_drive=15000, F_kin=14850,
                        k0=1e8 * 1e3 / 30, alpha=0.004, a=1e-5)
    t, x = ss.synth(rig, sample_interval=0.02, duration=300, resolution=0, sensor_noise=0, seed=3)
    xi = x - 3e-5 * t
    mu = (15000 - 1e8 * (xi - xi.mean())) / 25e3
    return t, 3e-5 * t + np.random.default_rng(3).normal(0, 5e-9, t.size), mu


def test_the_rig_case_is_the_command_lines_json_to_the_last_bit(tmp_path):
    t, load_point, mu = rig_record()
    expected = command_line_fields(
        tmp_path, {"t": t, "x": load_point, "channel": mu},
        ["--force-column", "channel", "--force-units", "mu", "--normal-stress", "10MPa", "--contact-area", "0.0025",
         "--machine-stiffness", "1e8", "--slider-mass", "2", "--compare-case", "rig", "--fit", "alpha,a"])
    got = ss.analyze(t, load_point, force=mu, force_units="mu", normal_stress=10, contact_area=25e-4,
                     machine_stiffness=1e8, slider_mass=2, compare="rig", fit="alpha,a").to_dict()
    del got["points"]
    assert got["compare_case"] == "rig" and got["model_parameters"]["M"] == 2 and "mu" not in got
    assert_same_fields(got, expected)


def test_a_force_record_is_the_command_lines_json_to_the_last_bit(tmp_path):
    t, load_point, mu = rig_record()
    expected = command_line_fields(
        tmp_path, {"t": t, "x": load_point, "channel": mu},
        ["--force-column", "channel", "--force-units", "mu", "--normal-force", "25000", "--observable", "force",
         "--fit", "power-law"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = ss.analyze(t, load_point, force=mu, force_units="mu", normal_force=25000, observable="force",
                         fit="power-law").to_dict()
    del got["points"]
    assert got["observable"]["spectrum"] == "C_F" and got["mean_force"] > 0 and "power_law_fit" in got
    assert_same_fields(got, expected)


def _header_line(prefix):
    """Lines before the CSV's column line and the line itself: '#' comments are skipped."""
    with open(f"{prefix}.csv") as f:
        return next(k for k, line in enumerate(f) if not line.startswith("#")) + 1

