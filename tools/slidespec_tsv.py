"""slidespec's TSV tables: '#' lines (`# key = value  # note`, or prose), a column line
(plain or '#'-prefixed; before the first row, the last one, a plain one over a '#' one),
then tab-separated rows of numbers.

The one reader of them: the slidespec package reads tables with it (a copy in the package
as slidespec._tsv), and so do the tools beside it, which must run where the package is not
built (the command line draws its figures with tools/plot_spectra.py). Standard library only.
"""

import re

_KEY_VALUE = re.compile(r"^([A-Za-z_]\w*)\s*=\s*(.*)$")
_NOTE = re.compile(r"\s{2,}#\s?")
_COLUMN_NAME = re.compile(r"[A-Za-z_]\w*")


class Table:
    """A table as written: `values` {key: value text} and `notes` {key: the note after
    '  #'} of its KEY = VALUE lines (a later line wins), `comments` the other '#' lines'
    text in order, `names` its columns and `rows` its rows (lists of floats)."""

    def __init__(self, path):
        self.path = path
        self.values, self.notes, self.comments = {}, {}, []
        self.names, self.rows = None, []

    def columns(self):
        """{name: [value of each row]}."""
        return {name: [row[i] for row in self.rows] for i, name in enumerate(self.names)}


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def _column_line(text):
    """The names of a column line (two or more names, tab-separated), else None."""
    names = [name.strip() for name in text.split("\t")]
    return names if len(names) >= 2 and all(_COLUMN_NAME.fullmatch(n) for n in names) else None


def parse(text, path):
    """The Table of `text` (read from `path`, which errors name). Raises ValueError naming
    the file and line for a data row before the column line, a row with another number of
    fields, a field that is not a number, or no column line."""
    table = Table(path)
    plain_names = False
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        if line.startswith("#"):
            body = line[1:].strip()
            if not table.rows and not plain_names and (names := _column_line(line[1:])):
                table.names = names
            elif match := _KEY_VALUE.match(body):
                value, note = (_NOTE.split(match.group(2), maxsplit=1) + [""])[:2]
                table.values[match.group(1)] = value.strip()
                table.notes[match.group(1)] = note.strip()
            else:
                table.comments.append(body)
            continue
        fields = line.split("\t") if "\t" in line else line.split()
        # A plain column line: the first such line before any row, of names. Anything else
        # is a row ("1,2,3", a CSV's, is a row with a field that is not a number).
        if not table.rows and not plain_names and not all(_is_number(field) for field in fields) \
                and all(_COLUMN_NAME.match(field.strip()) for field in fields):
            table.names, plain_names = [field.strip() for field in fields], True
            continue
        if not all(_is_number(field) for field in fields):
            bad = next(field for field in fields if not _is_number(field)).strip()
            comma = " (a table's fields are separated by tabs)" if "," in bad else ""
            raise ValueError(f"{path}: line {number}: '{bad}' is not a number{comma}")
        if table.names is None:
            raise ValueError(f"{path}: line {number}: a data row before the column line")
        if len(fields) != len(table.names):
            raise ValueError(f"{path}: line {number}: {len(fields)} fields, the column line has {len(table.names)}")
        table.rows.append([float(field) for field in fields])
    if table.names is None:
        raise ValueError(f"{path}: no column line (omega ...): not a slidespec table")
    return table


def read(path):
    """The Table of the file at `path` (UTF-8); OSError when it cannot be read."""
    with open(path, encoding="utf-8") as f:
        return parse(f.read(), path)
