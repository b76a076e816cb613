"""Reading the command line's outputs: a run's, a sweep's or an analysis's TSV or JSON."""

import errno as _errno
import json as _json
import math as _math
import os as _os
import re as _re
import stat as _stat

from . import _core, _tsv
from ._analysis import Analysis
from ._parameters import Parameters
from ._results import Result


# The landmarks PREFIX.json holds, in its order (some only with drive="spring").
_LANDMARK_KEYS = tuple(row["key"] for row in _core.landmark_table() if row["json"] != "never")
_PARAMETER_KEY = _re.compile(r"^(%s)(_\d+)?$" % "|".join(_re.escape(k.removesuffix("_l"))
                                                        for k in _core.parameter_keys()))
_SUB_BAND = _re.compile(r"^sub_band (\d+): omega (\S+) \.\. (\S+), dt = (\S+) s, duration = (\S+) s, "
                        r"warm_up = (\S+) s at dt (\S+) s, shadow = (true|false), realizations = (\d+)")
# A run's TSV lines that repeat what PREFIX.json holds elsewhere: the realizations summed over
# the sub-bands, a spring's mean_speed (its v), and the columns derived from C_x (omega^2 C_x,
# M^2 omega^4 C_x) and from the parameters (Eq. (1), eq1()).
_RUN_TABLE_ONLY = ("realizations", "mean_speed")
_RUN_DERIVED_COLUMNS = ("C_v", "C_F", "C_eq1")
# A run's per-point estimator: the TSV's code, the JSON's word.
_ESTIMATORS = {0.0: "plain", 1.0: "forcing", 2.0: "shadow"}
# A run's per-point theory kind: the TSV's code, the JSON's word.
_THEORY_KINDS = {0.0: "none", 1.0: "first_order", 2.0: "second_order", 3.0: "quasi_static"}


def _number(text):
    """A value as PREFIX.json holds it: an int without '.', 'e' or 'E', else a float, true and
    false as bools, any other text as text."""
    try:
        value = float(text)
    except ValueError:
        return {"true": True, "false": False}.get(text, text)
    return int(text) if _re.fullmatch(r"[+-]?\d+", text) else value


def _read_table(text, path):
    """A TSV of the command line (_tsv's format); a run's in the keys and types of its
    PREFIX.json."""
    table = _tsv.parse(text, path)
    if "omega" not in table.names:
        raise ValueError(f"{path}: no omega column: not a slidespec table")
    data = {}
    parameters, landmarks = {}, {}
    for body in table.comments:
        if body.startswith("slidespec ") and "=" not in body:
            data["slidespec_version"] = body.split()[1]
        elif match := _SUB_BAND.match(body):
            _, low, high, dt, duration, warm_up, warm_up_dt, shadow, count = match.groups()
            data.setdefault("sub_bands", []).append(
                {"omega_low": float(low), "omega_high": float(high), "dt": float(dt),
                 "duration": float(duration), "warm_up": float(warm_up), "warm_up_dt": float(warm_up_dt),
                 "shadow": shadow == "true", "realizations": int(count)})
    for key, value in table.values.items():
        note = table.notes[key]
        if _PARAMETER_KEY.match(key):
            parameters[key] = _number(value)
        elif key in _LANDMARK_KEYS:  # doubles, as the JSON holds them ("0" is 0.0)
            landmarks[key] = value == "true" if value in ("true", "false") else float(value)
        elif key == "measured_mean_speed":
            error = _re.search(r"\+-\s*(\S+)", note)
            data[key] = {"value": float(value), "standard_error": float(error.group(1)) if error else None}
        elif key == "seed":
            data.setdefault("request", {})["seed"] = int(value)
        elif key == "control_variate":
            data.setdefault("request", {})["control_variate"] = value
        elif key == "reached_precision":
            data[key] = _number(value)
            if target := _re.search(r"\(target (\S+)\)", note):
                data.setdefault("request", {})["precision"] = float(target.group(1))
        elif key == "theory_kind":
            data[key] = value
            reason = note.partition("; ")[2]
            if reason:
                data["theory_kind_note"] = reason
        elif key == "stationary":
            data[key] = _number(value)
            if note:
                data["stationarity"] = note
        else:
            data[key] = _number(value)
    rows = [dict(zip(table.names, row)) for row in table.rows]
    if "rows" in data and len(rows) != data.pop("rows"):
        raise ValueError(f"{path}: {len(rows)} point rows where its header counts {int(table.values['rows'])}: "
                         "the table was cut short or edited")
    if parameters:
        data["parameters"] = parameters
    if landmarks:
        if "forces_can_stall" not in landmarks:  # the TSV's header leaves it out
            landmarks["forces_can_stall"] = Parameters.from_dict(parameters, data.get("case", "reference")
                                                                 ).landmarks["forces_can_stall"]
        data["landmarks"] = {key: landmarks[key] for key in _LANDMARK_KEYS if key in landmarks}
    if "complete" in data:  # a run's table
        data.setdefault("label", data.get("case"))  # printed only when it differs from the case
        for key in _RUN_TABLE_ONLY:
            data.pop(key, None)
        rows = [{name: (_ESTIMATORS.get(value, value) if name == "estimator" else
                        _THEORY_KINDS.get(value, value) if name == "theory_kind" else
                        value if _math.isfinite(value) else None)
                 for name, value in row.items() if name not in _RUN_DERIVED_COLUMNS} for row in rows]
    data["points"] = rows
    return data


_MOST_TABLE_BYTES = 1 << 30


_SWEEP_RUN = _re.compile(r"^# run_\d+ = (.*)  # (.+)$")


def _sweep_runs(text, path):
    """The files of a sweep's runs, beside the sweep's own table, each with the label the
    sweep gives its run; None for any other file."""
    directory = _os.path.dirname(_os.fspath(path))
    if text.startswith("# slidespec ") and " sweep: " in text.split("\n", 1)[0]:
        return [(_os.path.join(directory, m.group(2)), m.group(1)) for line in text.splitlines()
                if (m := _SWEEP_RUN.match(line))]
    if text.lstrip().startswith("{"):
        try:
            data = _json.loads(text)
        except _json.JSONDecodeError:
            return None
        if isinstance(data, dict) and "runs" in data and "points" not in data:
            return [(_os.path.join(directory, run["table"]), run.get("label")) for run in data["runs"]]
    return None


def _sweep_member(sweep, index, path, label):
    """Run `index` of a sweep, read from its own file, which must still hold that run."""
    result = read(path)
    if label is not None and result.label != label:
        raise ValueError(f"{sweep}: run_{index} is '{label}', but {path} holds '{result.label}': "
                         "the sweep's files no longer agree")
    return result


def read(path):
    """Reads an output of the command line (`slidespec run`, `theory`, `analyze`, `merge`)
    as a Result (an Analysis for analyze's output); a `sweep`'s combined table as a list of
    Results, one per run, read from the runs' own files it names.

    path: PREFIX.tsv or PREFIX.json (both to every bit: each number is printed in the
    shortest form that reads back as the same double). The TSV's column line may be plain
    or start with '#'. Columns keep the file's
    units: omega [rad/s]; C_x, stderr, theory [m^2 s]. Raises OSError when the
    file cannot be read (a directory, a device, a pipe, or over 1 GiB: a table is a few
    kB) and ValueError when it is not a slidespec table."""
    with open(path, "rb", buffering=0) as f:
        info = _os.fstat(f.fileno())
        if not _stat.S_ISREG(info.st_mode):
            raise OSError(_errno.EINVAL, "not a regular file (a slidespec table is a file)", str(path))
        if info.st_size > _MOST_TABLE_BYTES:
            raise OSError(_errno.EFBIG, f"{info.st_size} bytes, more than a slidespec table's "
                          f"{_MOST_TABLE_BYTES}", str(path))
        raw = f.read(_MOST_TABLE_BYTES + 1)
    if len(raw) > _MOST_TABLE_BYTES:
        raise OSError(_errno.EFBIG, f"more than a slidespec table's {_MOST_TABLE_BYTES} bytes", str(path))
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text ({e.reason} at byte {e.start}): not a slidespec table") from None
    if runs := _sweep_runs(text, path):
        return [_sweep_member(path, k, run, label) for k, (run, label) in enumerate(runs)]
    if text.lstrip().startswith("{"):
        try:
            data = _json.loads(text)
        except _json.JSONDecodeError as e:
            raise ValueError(f"{path}: not valid JSON ({e})") from None
        if not isinstance(data, dict) or "points" not in data:
            raise ValueError(f"{path}: not a slidespec result (no points)")
    else:
        data = _read_table(text, path)
    if "record" in data or "usable_band" in data:
        return Analysis(data)
    return Result(data)
