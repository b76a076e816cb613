"""Numbers and counts as the command line takes them."""

import numpy as _np


_MOST_U64 = 2**64 - 1
_MOST_INT = 2**31 - 1


def _whole(name, value, largest):
    """A count or seed as the command line takes it: an int (not bool, not float) in 0..largest."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name}: expected a whole number (int), got {type(value).__name__} {value!r}")
    if not 0 <= int(value) <= largest:
        raise ValueError(f"{name}: {value} is outside 0..{largest}")
    return int(value)


def _real(name, value):
    """A real number as the command line takes it: int or float (not bool, not text)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(value).__name__} {value!r}")
    return float(value)


def _pair(name, value):
    """A band (low, high) as the command line's "LOW HIGH": two numbers, not text."""
    if isinstance(value, (str, bytes)) or _np.ndim(value) != 1 or len(value) != 2:
        raise TypeError(f"{name}: expected a pair (low, high), got {type(value).__name__} {value!r}")
    return (_real(f"{name} low", value[0]), _real(f"{name} high", value[1]))


def _samples(name, values):
    """A record's channel as the command line reads a column: one real number per sample,
    in a 1-D array (numpy would flatten a table and read numeric text silently)."""
    array = _np.asarray(values)
    if array.dtype.kind not in "iuf":
        raise TypeError(f"{name}: expected an array of numbers, got {type(values).__name__} of dtype {array.dtype}")
    if array.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, one value per sample, got shape {array.shape}")
    if array.size == 0:
        raise ValueError(f"{name}: an empty array; a record needs its samples")
    return array.astype(float)
