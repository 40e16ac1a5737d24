"""Columns of the CSV files of a run folder, read by header name, with errors naming file and line."""

import csv
import math

from .errors import ReportInputError


def number(text):
    """A number of a CSV cell; an empty cell (e.g. a NEES of an unusable covariance) is NaN."""
    return float(text) if text != "" else math.nan


def read_header(path):
    """The column names of the CSV file `path` (its first line); [] for an empty file."""
    try:
        f = open(path, newline="", encoding="utf-8")
    except OSError as e:
        raise ReportInputError(f"{path}: cannot read: {e.strerror}") from None
    with f:
        return next(csv.reader(f), None) or []


def read_columns(path, columns):
    """Reads the columns named in `columns` (name -> converter, e.g. float or str) of the CSV
    file `path` (first line: header; other columns are ignored). Returns name -> list of values.
    Raises ReportInputError for a missing column or a cell the converter refuses."""
    try:
        f = open(path, newline="", encoding="utf-8")
    except OSError as e:
        raise ReportInputError(f"{path}: cannot read: {e.strerror}") from None
    with f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header is None:
            raise ReportInputError(f"{path}:1: empty file, expected a header line")
        index = {}
        for name in columns:
            if name not in header:
                raise ReportInputError(
                    f"{path}:1: no column '{name}' (the header has: {', '.join(header)})")
            index[name] = header.index(name)
        out = {name: [] for name in columns}
        items = [(name, index[name], convert, out[name]) for name, convert in columns.items()]
        for line, row in enumerate(reader, start=2):
            if not row:
                continue
            try:
                for name, i, convert, values in items:
                    values.append(convert(row[i]))
            except (ValueError, IndexError):
                cell = row[i] if i < len(row) else "(missing)"
                raise ReportInputError(
                    f"{path}:{line}: column '{name}': unexpected value '{cell}'") from None
        return out
