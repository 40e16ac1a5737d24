"""A run folder written by `statebench run` (docs/cli.md), read for the run report.

Always there: run.json, and per estimator <label>/metrics.json, diagnostics.json,
estimate.csv, estimator_config.yaml; sumo/net.net.xml. The run details
(docs/estimate-format.md, "Run details") are read when present: reference.csv and
gnss_fixes.csv in the folder, <label>/errors.csv and <label>/measurements.csv. A missing file
of those leaves its plots out, with a note saying which file is missing.
"""

import json
import math
import os

from .csv_columns import number, read_columns, read_header
from .errors import ReportInputError

ERROR_AXES = [  # (column, sigma column, title, unit)
    ("e_x", "sigma_x", "x (east)", "m"),
    ("e_y", "sigma_y", "y (north)", "m"),
    ("e_z", "sigma_z", "z (up)", "m"),
    ("e_along", "sigma_along", "along track", "m"),
    ("e_across", "sigma_across", "across track", "m"),
    ("e_roll", "sigma_roll", "roll", "rad"),
    ("e_pitch", "sigma_pitch", "pitch", "rad"),
    ("e_yaw", "sigma_yaw", "yaw", "rad"),
    ("e_v_long", "sigma_v_long", "longitudinal velocity", "m/s"),
]
# Axes an errors.csv written before they existed does not have (their plots are left out).
OPTIONAL_ERROR_COLUMNS = {"e_roll", "e_pitch"}


def error_axes(columns):
    """The ERROR_AXES present in every one of `columns` (dicts of errors.csv columns)."""
    return [a for a in ERROR_AXES if all(a[0] in c for c in columns)]


def _seconds(t_ns_text):
    return int(t_ns_text) * 1e-9


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        raise ReportInputError(f"{path}: cannot read: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ReportInputError(f"{path}:{e.lineno}:{e.colno}: not JSON: {e.msg}") from None


def read_text(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return None


class Estimator:
    """One estimator's files in the run folder."""

    def __init__(self, run_dir, entry):
        self.label = entry.get("label", "")
        if not self.label:
            raise ReportInputError(f"{os.path.join(run_dir, 'run.json')}: an estimator without a label")
        self.type = entry.get("type", "")
        self.dir = os.path.join(run_dir, self.label)
        self.metrics = entry.get("metrics") or {}
        metrics_file = os.path.join(self.dir, "metrics.json")
        if not self.metrics and os.path.isfile(metrics_file):
            self.metrics = read_json(metrics_file)
        diagnostics_file = os.path.join(self.dir, "diagnostics.json")
        self.diagnostics = read_json(diagnostics_file) if os.path.isfile(diagnostics_file) else None
        self.config_text = read_text(os.path.join(self.dir, "estimator_config.yaml"))

    def file(self, name):
        return os.path.join(self.dir, name)

    def has(self, name):
        return os.path.isfile(self.file(name))

    def estimate_track(self):
        """t [s], x, y of estimate.csv (None when the file is missing)."""
        if not self.has("estimate.csv"):
            return None
        c = read_columns(self.file("estimate.csv"), {"t_ns": _seconds, "p_x": float, "p_y": float})
        return c["t_ns"], c["p_x"], c["p_y"]

    def errors(self):
        """Columns of errors.csv (t in s; NaN for empty cells), or None when missing."""
        if not self.has("errors.csv"):
            return None
        columns = {"t_ns": _seconds, "status": str, "nees_pose": number, "nees_position": number}
        header = read_header(self.file("errors.csv"))
        for error, sigma, _, _ in ERROR_AXES:
            if error in OPTIONAL_ERROR_COLUMNS and error not in header:
                continue
            columns[error] = number
            columns[sigma] = number
        return read_columns(self.file("errors.csv"), columns)

    def measurements(self):
        """t [s], sensor, verdict of measurements.csv, or None when missing."""
        if not self.has("measurements.csv"):
            return None
        c = read_columns(self.file("measurements.csv"), {"t_ns": str, "sensor": str, "verdict": str})
        return c


class RunFolder:
    def __init__(self, run_dir):
        if not os.path.isdir(run_dir):
            raise ReportInputError(f"{run_dir}: no such run folder")
        self.dir = run_dir
        self.summary = read_json(os.path.join(run_dir, "run.json"))
        self.estimators = [Estimator(run_dir, e) for e in self.summary.get("estimators", [])]
        if not self.estimators:
            raise ReportInputError(f"{os.path.join(run_dir, 'run.json')}: no estimators")

    def file(self, name):
        return os.path.join(self.dir, name)

    def has(self, name):
        return os.path.isfile(self.file(name))

    def outages(self):
        """GNSS outage windows [(begin_s, end_s)] from the estimators' metrics.json."""
        windows = []
        for e in self.estimators:
            for o in e.metrics.get("during_outages") or []:
                w = (o.get("begin_s"), o.get("end_s"))
                if None not in w and all(math.isfinite(x) for x in w) and w not in windows:
                    windows.append(w)
            if windows:
                break
        return windows

    def reference(self):
        """t [s], x, y of reference.csv, or None when missing."""
        if not self.has("reference.csv"):
            return None
        c = read_columns(self.file("reference.csv"), {"t_ns": _seconds, "x": float, "y": float})
        return c["t_ns"], c["x"], c["y"]

    def gnss_fixes(self):
        """Columns of gnss_fixes.csv (t_ns kept as text, to pair with verdicts), or None."""
        if not self.has("gnss_fixes.csv"):
            return None
        return read_columns(self.file("gnss_fixes.csv"),
                            {"t_ns": str, "sensor": str, "x": float, "y": float})

    def net_file(self):
        path = self.file(os.path.join("sumo", "net.net.xml"))
        return path if os.path.isfile(path) else None
