"""ss.analyze with the command line's options on numpy arrays: channels, windows, the
power-law fit and the joint model fit on the record's terms (docs/analysis.md)."""

import json
import os
import pathlib
import subprocess
import warnings

import numpy as np
import pytest

import slidespec as ss

DT = 0.02  # [s]
MACHINE = ss.Parameters(drive="spring", k_drive=1e3, alpha=0.5, a=1e-3)
BASALT = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "realdata" / "velstep4_BRAVA_expb819_basalt.txt"
CLI = os.environ.get("SLIDESPEC", "slidespec")


def sensor_noise():
    """White sensor noise whose floor meets the model at 40 rad/s."""
    level = ss.theory(MACHINE, 40.0)
    return float(np.sqrt(2 * np.pi * level / DT))


def test_joint_fit_recovers_alpha_and_a_on_the_machines_terms():
    t, x = ss.synth(MACHINE, sample_interval=DT, duration=2000, resolution=0, sensor_noise=sensor_noise(), seed=1)
    start = MACHINE.replace(alpha=1.0, a=3e-3)
    a = ss.analyze(t, x, compare=start, fit="alpha,a")
    fit = a.model_fit
    assert a.ok and fit["ok"], fit["failure"]
    assert fit["names"] == ["alpha", "a", "floor"]
    for name, true in (("alpha", 0.5), ("a", 1e-3)):
        value = fit["parameters"][name]
        assert abs(value["value"] - true) < 3 * value["standard_error"], (name, value)
    assert np.shape(fit["covariance"]) == (3, 3)
    assert "N and alpha are not separated" in fit["undetermined"]
    assert a.model_parameters["alpha"] == pytest.approx(fit["parameters"]["alpha"]["value"])
    assert a.model_parameters["v"] == pytest.approx(a.mean_speed)  # the record's measured v
    inside = np.isfinite(a.residual)
    assert inside.sum() == fit["points"]
    assert np.all(np.abs(a.residual[inside]) < 5)
    # The list form is the same fit.
    same = ss.analyze(t, x, compare=start, fit=["alpha", "a"])
    assert same.model_fit["parameters"] == fit["parameters"]


def test_a_model_that_does_not_describe_the_record_is_a_failed_fit():
    rng = np.random.default_rng(2)
    t = DT * np.arange(20000)
    # A random walk with a line at 5 rad/s: no spring-driven slider makes a line.
    walk = np.cumsum(rng.normal(0, 1e-7, t.size)) + 1e-4 * t + 3e-6 * np.sin(5 * t)
    with pytest.warns(ss.ModelWarning, match="model fit FAILED: chi2/dof"):  # as the command line says
        a = ss.analyze(None, walk, dt=DT, compare=MACHINE, fit="alpha,a")
    assert not a.ok
    assert not a.model_fit["ok"]
    assert "chi2/dof" in a.model_fit["failure"]


def test_power_law_fit_and_floor():
    rng = np.random.default_rng(3)
    n = 20000
    walk = np.cumsum(rng.normal(0, 1e-7, n)) + rng.normal(0, 3e-7, n)
    a = ss.analyze(None, walk, dt=DT, fit="power-law")
    fit = a.power_law_fit
    assert fit["ok"], fit["failure"]
    assert abs(fit["slope"] + 2) < 3 * fit["slope_error"]
    assert abs(fit["floor"] - (3e-7) ** 2 * DT / (2 * np.pi)) < 3 * fit["floor_error"]
    assert np.isfinite(a.fit).any()


def test_force_channels_from_arrays():
    rng = np.random.default_rng(4)
    n, rms = 20000, 0.05  # kN
    t = DT * np.arange(n)
    force = 10 + rms * rng.normal(size=n)
    a = ss.analyze(t, None, force=force, force_units="kN")
    assert a.observable["name"] == "force"
    white = (rms * 1e3) ** 2 * DT / (2 * np.pi)
    inside = (a.C_low <= white) & (white <= a.C_high)
    assert inside.mean() >= 0.85
    # mu times a normal stress column and an area, as the command line reads it.
    mu = 0.6 + 0.001 * rng.normal(size=n)
    sigma = np.full(n, 20.0)
    b = ss.analyze(t, None, force=mu, force_units="mu", normal_stress=sigma, contact_area=25e-4)
    assert b.mean_force == pytest.approx(0.6 * 20e6 * 25e-4, rel=1e-3)
    with pytest.raises(ValueError, match="contact"):
        ss.analyze(t, None, force=mu, force_units="mu", normal_stress=sigma)


def test_machine_stiffness_drives_the_compared_case_through_a_spring():
    table = np.loadtxt(BASALT, skiprows=1)
    a = ss.analyze(table[:, 0], table[:, 1], units="um", force=table[:, 2], force_units="mu",
                   normal_stress=table[:, 3], contact_area=25e-4, machine_stiffness=5e7,
                   window=(11608, 11674), compare="reference")
    assert a.observable["name"] == "slip"
    assert a.model_parameters["drive"] == "spring"
    assert a.model_parameters["k_drive"] == pytest.approx(5e7)
    assert a.model_parameters["v"] == pytest.approx(a.mean_speed, rel=1e-6)
    assert np.all(np.isfinite(a.theory))


def test_the_rig_case_is_built_from_the_record_and_the_rigs_knowns():
    # A rig's record: the load point v t and the spring's force, mu x 10 MPa x 25 cm^2 = 15 kN.
    rig = ss.Parameters("reference", drive="spring", k_drive=1e8, v=3e-5, F_drive=15000, F_kin=14850,
                        k0=1e8 * 1e3 / 30, alpha=0.004, a=1e-5)
    t, x = ss.synth(rig, sample_interval=0.02, duration=600, resolution=0, sensor_noise=0, seed=3)
    xi = x - 3e-5 * t
    mu = (15000 - 1e8 * (xi - xi.mean())) / 25e3
    load_point = 3e-5 * t + np.random.default_rng(3).normal(0, 5e-9, t.size)  # read with 5 nm of noise
    a = ss.analyze(t, load_point, force=mu, force_units="mu", normal_stress=10, contact_area=25e-4,
                   machine_stiffness=1e8, slider_mass=2, compare="rig", fit="alpha,a")
    assert a.model_parameters["F_drive"] == pytest.approx(15000, rel=1e-5)  # the stretch's mean
    assert a.model_parameters["F_kin"] == pytest.approx(0.99 * a.model_parameters["F_drive"], rel=1e-9)  # held at 1%
    assert a.model_parameters["M"] == 2
    assert any("mu = 0.6" in note for note in a.notes), a.notes
    fit = a.model_fit["parameters"]
    assert a.ok and abs(fit["alpha"]["value"] - 0.004) < 3 * fit["alpha"]["standard_error"]
    with pytest.raises(ValueError, match="^slider_mass: used only by compare rig"):
        ss.analyze(t, load_point, force=mu, force_units="mu", normal_stress=10, contact_area=25e-4,
                   machine_stiffness=1e8, slider_mass=2)


def basalt():
    """The measured basalt record: t [s], x [um], friction mu, normal stress [MPa]."""
    return np.loadtxt(BASALT, skiprows=1, unpack=True)


def test_a_resolution_in_the_wrong_unit_warns_as_the_command_line_does(tmp_path):
    t, x, _, _ = basalt()
    # 0.1 is 0.1 m in Python (0.1 um was meant): the floor lies above the spectrum everywhere.
    with pytest.warns(ss.RecordWarning) as caught:
        a = ss.analyze(t, x, units="um", window=(11608, 11674), resolution=0.1)
    messages = [str(w.message) for w in caught]
    assert any("no usable band" in m and "resolution or sensor_noise" in m and "metres" in m for m in messages)
    assert any("reads finer" in m for m in messages), messages  # its readings are not on a 0.1 m grid
    done = subprocess.run([CLI, "analyze", str(BASALT), "--window", "11608:11674", "--resolution", "0.1m",
                           "--out", str(tmp_path / "basalt"), "--no-plot"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "no usable band" in done.stderr and "reads finer" in done.stderr
    expected = json.loads((tmp_path / "basalt.json").read_text())
    assert a.usable_band == expected["usable_band"] and a.usable_band["omega_high"] == 0
    assert a.ok == expected["ok"]  # no fit failed: the files hold what they claim


def test_a_band_lost_to_the_tenth_of_the_floor_is_not_blamed_on_the_unit(tmp_path):
    # 0.6 um: the floor is below C_x at the lowest point but above a tenth of it; the warnings
    # are the command line's, word for word.
    t, x, _, _ = basalt()
    with pytest.warns(ss.RecordWarning) as caught:
        ss.analyze(t, x, units="um", window=(11608, 11674), resolution=0.6e-6)
    messages = [str(w.message) for w in caught]
    done = subprocess.run([CLI, "analyze", str(BASALT), "--window", "11608:11674", "--resolution", "0.6um",
                           "--quiet", "--no-plot", "--out", str(tmp_path / "basalt")], capture_output=True, text=True)
    printed = [line.removeprefix("slidespec: warning: ") for line in done.stderr.splitlines() if "warning" in line]
    assert any(m.startswith("no usable band: at the lowest point") and "by the factor" in m for m in messages)
    assert not any("wrong unit" in m or "not white" in m for m in messages), messages
    assert [m.replace("resolution given", "--resolution given") for m in messages] == printed, (messages, printed)


def test_a_well_read_record_does_not_warn():
    t, x, _, _ = basalt()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = ss.analyze(t, x, units="um", window=(11608, 11674), resolution=1e-7)
    assert a.usable_band["omega_high"] > a.usable_band["omega_low"]


def test_leaky_points_and_an_implausible_speed_warn():
    t, x = ss.synth("reference", sample_interval=1e-3, duration=100, resolution=0, sensor_noise=0, seed=1)
    with pytest.warns(ss.RecordWarning, match="leakage") as caught:
        a = ss.analyze(t, x)
    assert f"{a.estimator['leaky_points']} points" in str(caught[0].message)
    assert a.estimator["leaky_points"] > 0 and a.leaky.sum() == a.estimator["leaky_points"]
    bt, bx, _, _ = basalt()
    with pytest.warns(ss.RecordWarning, match="implausible") as caught:
        ss.analyze(bt, bx, window=(11608, 11674))  # microns read as metres: 3 m/s
    assert "units" in str(caught[0].message)


def test_a_slope_band_beyond_the_usable_band_warns():
    t, x = ss.synth("reference", sample_interval=1e-2, duration=300, resolution=0.5e-6, sensor_noise=0.25e-6, seed=2)
    sensor = dict(resolution=0.5e-6, sensor_noise=0.25e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inside = ss.analyze(t, x, fit_slope=(3, 15), **sensor)
    assert not inside.slope_fit["reaches_floor"] and inside.usable_band["omega_high"] < 100
    with pytest.warns(ss.RecordWarning, match="slope band reaches beyond the usable band"):
        beyond = ss.analyze(t, x, fit_slope=(3, 100), **sensor)
    assert beyond.slope_fit["reaches_floor"] and beyond.ok


@pytest.mark.parametrize("fit", ["beta", "alpha,N", ["alpha", "beta"]])
def test_a_fit_of_what_no_fit_varies_says_so_as_the_command_line_does(fit, tmp_path):
    t, x, _, _ = basalt()
    with pytest.raises(ValueError) as error:
        ss.analyze(t, x, units="um", window=(11608, 11674), compare="reference", fit=fit)
    name = "beta" if "beta" in fit else "N"
    done = subprocess.run([CLI, "analyze", str(BASALT), "--window", "11608:11674", "--compare-case", "reference",
                           "--fit", fit if isinstance(fit, str) else ",".join(fit), "--no-plot", "--quiet",
                           "--out", str(tmp_path / "never")], capture_output=True, text=True)
    assert f"'{name}' is not a model parameter a fit can vary" in done.stderr
    assert str(error.value) == done.stderr.strip().removeprefix("slidespec: error: --")


def test_messages_name_pythons_keywords_not_the_command_lines_options():
    t, x, _, _ = basalt()
    for kwargs, keyword in [(dict(omega_max=1e9), "omega_max"), (dict(window=(0, 1)), "window"),
                            (dict(dt=-1.0, t=None), "dt")]:
        call = dict(t=t, x=x, units="um") | kwargs
        with pytest.raises(ValueError) as error:
            ss.analyze(call.pop("t"), call.pop("x"), **call)
        assert str(error.value).startswith(keyword), str(error.value)
        assert "--" not in str(error.value), str(error.value)
    with pytest.raises(ValueError, match="^precision") as error:
        ss.run("reference", precision=2)
    with pytest.raises(ValueError, match="^omega_max") as error:
        ss.run("reference", omega_max=1e12)
    assert "--" not in str(error.value)
    # A record of a force alone has no x: without a force either, the message says what to give.
    with pytest.raises(ValueError) as error:
        ss.analyze(t, None)
    assert "force=" in str(error.value) and "--" not in str(error.value)
    # The notes of a record name the keywords too.
    a = ss.analyze(t, x, units="um")
    assert a.notes and not [note for note in a.notes if "--" in note], a.notes
    assert "resample=DT interpolates the whole record" in a.notes[0]
    step = 0.01 * np.arange(20000)  # a velocity step at 100 s
    x = np.where(step < 100, 1e-6 * step, 1e-4 + 1e-5 * (step - 100)) + np.random.default_rng(1).normal(0, 1e-8, step.size)
    a = ss.analyze(step, x)  # the step's own blocks are left out: no leakage from it
    note = a.notes[0]
    assert "(the field segments lists them)" in note and "window=(T0, T1) picks another" in note, note
    assert a.estimator["leaky_points"] == 0
    assert [s["kind"] for s in a.segments] == ["sliding", "step", "sliding"], a.segments


def test_the_force_channel_is_named_once():
    t, _, mu, _ = basalt()
    a = ss.analyze(t, None, force=mu, force_units="mu", normal_force=1e3, window=(11608, 11674))
    assert a.observable["channel"] == "force channel (mu) x normal force 1000 N"


def test_resampling_cuts_the_band_at_the_coarsest_interval_analysed():
    # The basalt record is sampled at 0.1 s, then 0.01 s; resampled onto the 0.01 s grid, the
    # stretch analysed lies in the 0.1 s part, where interpolation filters above acos(0.85)/0.1.
    t, x, _, _ = basalt()
    a = ss.analyze(t, x, units="um", resample="median")
    assert 0 < a.usable_band["omega_high"] <= np.arccos(0.85) / 0.1


def test_an_alpha_fit_into_the_stall_is_a_failed_fit_not_an_error():
    t, x, _, _ = basalt()
    with pytest.warns(ss.ModelWarning, match="FAILED"):
        a = ss.analyze(t, x, units="um", window=(11608, 11674), compare="reference", fit="alpha")
    assert not a.ok


def test_a_band_that_is_not_one_is_refused():
    t, x, _, _ = basalt()
    for band in ({"omega_max": -1}, {"omega_min": -5}, {"omega_min": 10, "omega_max": 1}):
        with pytest.raises(ValueError, match="omega_m"):
            ss.analyze(t, x, units="um", window=(11608, 11674), **band)


@pytest.mark.parametrize("arguments, error, words", [
    ({"x": np.zeros((2, 300))}, ValueError, "x: expected a 1-D array, one value per sample, got shape (2, 300)"),
    ({"t": np.arange(300.0).reshape(300, 1)}, ValueError, "t: expected a 1-D array"),
    ({"t": [], "x": []}, ValueError, "t: an empty array"),
    ({"x": []}, ValueError, "x: an empty array"),
    ({"x": [str(k) for k in range(300)]}, TypeError, "x: expected an array of numbers"),
    ({"t": np.arange(300.0).astype(str)}, TypeError, "t: expected an array of numbers"),
    ({"force": np.ones((2, 300)), "force_units": "N"}, ValueError, "force: expected a 1-D array"),
    ({"fit_slope": (1, 2, 3)}, TypeError, "fit_slope: expected a pair (low, high)"),
])
def test_a_channel_that_is_not_one_column_of_numbers_is_refused_naming_it(arguments, error, words):
    # numpy would flatten a table, read numeric text as numbers and pass an empty record on.
    call = {"t": np.arange(300) * DT, "x": np.arange(300) * 1e-7} | arguments
    with pytest.raises(error) as refused:
        ss.analyze(call.pop("t"), call.pop("x"), **call)
    assert words in str(refused.value)


def test_one_array_alone_is_named_as_the_times():
    """analyze(a) with one array takes it for t: the message says so, with its shape."""
    with pytest.raises(ValueError, match=r"x: no positions given \(the one array given is t, the sample times, "
                                         r"of shape \(3, 3, 3\)\)"):
        ss.analyze(np.ones((3, 3, 3)))
