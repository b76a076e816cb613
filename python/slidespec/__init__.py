"""slidespec: power spectra of frictional sliding noise, from Python.

The spring-block model of Xu, Zhou and Persson: a block pulled over a rough substrate
through N miniblocks that feel kinetic friction and a random force renewed every sliding
distance ~a. slidespec gives the spectrum C_x(omega) of the sliding-distance fluctuation
xi(t) = x(t) - v t, simulated with error bars (run) or exact in first order (theory), and
analyses measured records (analyze). The numbers are those of the `slidespec` command.

Units are SI throughout: omega in rad/s (angular frequency), C_x in m^2 s (two-sided, so
that its integral over all omega is <xi^2>), lengths in m, times in s, masses in kg.

    import slidespec as ss
    p = ss.Parameters("reference", alpha=0.4)
    r = ss.run(p, omega_min=1, omega_max=1e3, precision=0.05, seed=1, progress=True)
    r.omega, r.C_x, r.stderr, r.theory          # numpy arrays [rad/s], [m^2 s]

Errors: bad parameters or requests raise ValueError with the command line's message,
naming the key; files that cannot be read raise OSError. Ctrl-C during run() raises
KeyboardInterrupt carrying what the run accumulated as `error.result`; resume() continues it.
"""

from . import _core
from ._kinds import PrecisionWarning, ModelWarning, RecordWarning
from ._parameters import Parameters, parameter_table, cases
from ._theory import omegas, theory, spring_force_theory, eq1, long_time_motion
from ._results import Result
from ._runs import run, resume
from ._records import read
from ._analysis import Analysis, analyze, synth
from ._many import AnalysesInterrupted, Records, analyze_many

__version__ = _core.version
__all__ = ["Parameters", "parameter_table", "Result", "Analysis", "cases", "omegas", "theory", "spring_force_theory", "eq1", "long_time_motion", "run", "resume",
           "read", "analyze", "analyze_many", "AnalysesInterrupted", "Records", "synth", "PrecisionWarning", "ModelWarning", "RecordWarning"]
