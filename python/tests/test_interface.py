"""The module's surface as a notebook meets it: parameters that round-trip through their dicts,
and a namespace that holds the module's names only."""

import types

import pytest

import slidespec as ss


@pytest.mark.parametrize("case", ss.cases())
def test_parameters_round_trip_through_their_dict(case):
    p = ss.Parameters(case)
    assert ss.Parameters(**p.to_dict()) == p  # eta1 beside the v it derives from, as --params
    assert ss.Parameters.from_dict(p.to_dict()) == p


def test_parameters_round_trip_through_a_results_parameters():
    p = ss.Parameters("reference", N=12, alpha=0.4, drive="spring", k_drive=1e4)
    r = ss.run(p, omega_min=10, omega_max=100, realizations=4, seed=1, threads=1)
    assert ss.Parameters(**r.parameters) == p
    assert ss.Parameters(**r.parameters).landmarks == p.landmarks


def test_an_eta1_that_v_does_not_give_is_still_refused():
    with pytest.raises(ValueError, match="v and eta1: give one"):
        ss.Parameters(v=1e-3, eta1=5)
    p = ss.Parameters()
    with pytest.raises(ValueError, match="v and eta1: give one"):
        ss.Parameters(**(p.to_dict() | {"v": 2 * p["v"]}))


def test_the_namespace_holds_the_modules_names_only():
    public = {name for name in dir(ss) if not name.startswith("_")}
    assert public == set(ss.__all__), public ^ set(ss.__all__)
    assert not [name for name in public if isinstance(getattr(ss, name), types.ModuleType)]
    for name in ("np", "os", "re", "json", "math", "stat", "errno", "warnings", "Mapping"):
        assert not hasattr(ss, name), name
    assert issubclass(ss.RecordWarning, UserWarning)


def test_warnings_point_at_the_callers_line():
    # Forces that can stall the block, and realizations too short to tell.
    p = ss.Parameters("reference", N=7, F_drive=8, F_kin=6, k1=0)
    # The warning says why, as the result's stationarity does.
    with pytest.warns(ss.ModelWarning, match="not stationary: the random forces can stall") as caught:
        r = ss.run(p, omega_min=10, omega_max=100, realizations=4, seed=2, threads=2)
    assert any(r.stationarity in str(w.message) for w in caught)
    assert {w.filename for w in caught} == {__file__}
    t, x = ss.synth("reference", sample_interval=1e-3, duration=100, resolution=0, sensor_noise=0, seed=1)
    with pytest.warns(ss.RecordWarning, match="leakage") as caught:
        ss.analyze(t, x)
    assert [w.filename for w in caught] == [__file__]


def test_the_control_variate_switch_is_the_command_lines():
    p = ss.Parameters("reference")
    shadow = ss.run(p, omega_min=1, omega_max=7.5, realizations=16, seed=3, threads=2)
    plain = ss.run(p, omega_min=1, omega_max=7.5, realizations=16, seed=3, threads=2, control_variate="off")
    assert set(shadow.estimator) == {"shadow"} and set(plain.estimator) == {"forcing"}
    assert (shadow.stderr < plain.stderr).all()
    assert shadow.request["control_variate"] == "shadow" and plain.request["control_variate"] == "off"
    assert [band["shadow"] for band in shadow.sub_bands] == [True]
    with pytest.raises(ValueError, match="control_variate"):
        ss.run(p, omega_min=1, omega_max=7.5, realizations=16, control_variate=False)
