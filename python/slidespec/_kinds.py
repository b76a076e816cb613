"""The warnings slidespec gives: a run short of its precision, a model or a result outside
what it claims, a record that holds less than it seems."""



class PrecisionWarning(UserWarning):
    """A run ended without reaching the precision it was asked for (its work budget ran out)."""


class ModelWarning(UserWarning):
    """The parameters lie outside the first-order theory's validity, or a result is not
    what it claims (e.g. not stationary); the numbers are reported all the same."""


class RecordWarning(UserWarning):
    """A measured record's spectrum holds less than it seems, as `slidespec analyze` warns: no
    usable band (the sensor floor above the spectrum: resolution or sensor_noise in the wrong
    unit), a mean speed no friction experiment has (x in the wrong units), points the window's
    leakage may bias, or a quantization floor that is not white. The numbers are reported all
    the same."""
