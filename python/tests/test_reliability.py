"""Python's reliability: the interpreter exiting while a run works on another thread, a
spectrum of nothing, and arguments that would be accepted and ignored (run through ctest:
PYTHONPATH holds the built package)."""

import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import slidespec as ss

# A run of ~10 s at 0.5%: still working when the interpreter exits or Ctrl-C lands.
LONG_RUN = 'ss.run("reference", precision=0.005, threads=1)'


def run_child(code, timeout=120):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=timeout)


def test_the_interpreter_exits_cleanly_while_a_daemon_thread_runs():
    for _ in range(3):
        child = run_child(f"""
            import threading, time
            import slidespec as ss
            threading.Thread(target=lambda: {LONG_RUN}, daemon=True).start()
            time.sleep(0.5)
        """)
        assert child.returncode == 0, child.stderr
        assert "terminate called" not in child.stderr


def test_ctrl_c_in_join_then_exit_is_clean():
    child = run_child(f"""
        import os, signal, threading
        import slidespec as ss
        worker = threading.Thread(target=lambda: {LONG_RUN}, daemon=True)
        worker.start()
        threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()  # Ctrl-C
        try:
            worker.join()
        except KeyboardInterrupt:
            pass
    """)
    assert child.returncode == 0, child.stderr
    assert "terminate called" not in child.stderr


def test_a_constant_record_is_not_a_spectrum():
    t = np.arange(4000) * 0.01
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ss.analyze(t, np.full(t.size, 0.002))
    assert not result.ok


def test_a_progress_that_is_neither_a_flag_nor_a_callable_is_refused():
    with pytest.raises(TypeError, match="progress"):
        ss.run("reference", omega_min=100, omega_max=1000, precision=0.2, progress="yes")


@pytest.mark.parametrize("make", [
    lambda: ss.Parameters("reference", drive="spring", k_drive=[1e4]),
    lambda: ss.Parameters("reference").replace(alpha=(0.5,)),
    lambda: ss.Parameters("reference", N=np.array([30])),
])
def test_a_list_for_a_parameter_of_one_value_is_refused(make):
    with pytest.raises(ValueError, match="is a list; give one value"):
        make()


def test_touching_still_takes_a_list_of_levels():
    assert ss.Parameters("reference", levels=2, touching=[1, 2])


def test_too_many_threads_are_refused_as_on_the_command_line():
    with pytest.raises(ValueError, match="threads: must be 0 .* to 4096"):
        ss.run("reference", omega_min=100, omega_max=1000, precision=0.2, threads=10**9)


def test_messages_name_the_argument():
    with pytest.raises(TypeError, match="window: expected a pair"):
        ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, window="1:35")
    with pytest.raises(ValueError, match="parameter drive: b'spring'"):
        ss.Parameters("reference", drive=b"spring")


@pytest.mark.parametrize("call, error, names", [
    # 0 would be read as "no machine", the slip silently not taken
    (lambda x: ss.analyze(None, x, dt=0.01, machine_stiffness=0), ValueError, "machine_stiffness: 0"),
    (lambda x: ss.analyze(None, x, dt=0), ValueError, "dt: 0.0 s; without the sample times t"),
    (lambda x: ss.analyze(None, x), ValueError, "dt: 0.0 s; without the sample times t"),
    (lambda x: ss.analyze("record.csv", x), TypeError, "t: expected the sample times .* got the path 'record.csv'"),
    (lambda x: ss.analyze(None, x, dt=0.01, fit_slope=(1,)), TypeError, r"fit_slope: expected a pair .* \(1,\)"),
    (lambda x: ss.analyze(None, x, dt=0.01, fit_band=(1, "2")), TypeError, "fit_band high: expected a number"),
])
def test_bad_arguments_to_analyze_name_the_argument(call, error, names):
    x = np.arange(600) * 1e-6
    with pytest.raises(error, match=names):
        call(x)
