"""Errors the report package raises on bad input (exit code 2 of the entry points)."""


class ReportInputError(Exception):
    """Bad input: the message names the file, and the line and field when there are some."""
