"""The runs of a sweep's store (as SweepReportData gives them) split into cells: estimator x
value of the `by` axis; the worst runs per metric."""

import math


def value_key(text):
    """Sort key of axis values: numbers by value before words, words alphabetically."""
    try:
        return (0, float(text), "")
    except (TypeError, ValueError):
        return (1, 0.0, str(text))


def cell_values(data):
    return sorted({r["cell"] for r in data["runs"]}, key=value_key)


def cell_label(data, value):
    return f"{data['by']} = {value}" if data["by"] else "all runs"


class Cell:
    def __init__(self, estimator, value):
        self.estimator = estimator
        self.value = value
        self.runs = 0
        self.failed = 0
        self.no_estimate = 0  # ok runs where the estimator compared no epoch
        self.values = {}  # metric -> [(value, run)]


def split(data):
    """{(estimator, cell value): Cell}; a metric's values are the finite ones of ok runs whose
    estimator gave an estimate (compared > 0)."""
    cells = {}
    for estimator in data["estimators"]:
        for value in cell_values(data):
            cells[(estimator, value)] = Cell(estimator, value)
    for run in data["runs"]:
        for estimator in data["estimators"]:
            cell = cells[(estimator, run["cell"])]
            cell.runs += 1
            if run["status"] != "ok":
                cell.failed += 1
                continue
            metrics = run["metrics"].get(estimator, {})
            if not (metrics.get("compared") or 0) > 0:
                cell.no_estimate += 1
                continue
            for metric in data["metrics"]:
                v = metrics.get(metric)
                if v is not None and math.isfinite(v):
                    cell.values.setdefault(metric, []).append((v, run))
    return cells


def badness(metric, value, dof=None):
    """How bad a value is, larger is worse: a NEES by its distance to its degrees of freedom
    on a log scale (over- and under-confidence alike), availability by how low it is, every
    other metric (errors) by its value."""
    if dof:
        return abs(math.log(max(value, 1e-12) / dof))
    if "availability" in metric or metric.endswith("fraction"):
        return -value
    return value


def worst_runs(data, cells, metric, count):
    """The `count` worst (value, estimator, run) of a metric over every cell."""
    dof = (data.get("nees_bounds", {}).get(metric) or {}).get("dof")
    entries = []
    for cell in cells.values():
        for value, run in cell.values.get(metric, []):
            entries.append((badness(metric, value, dof), value, cell.estimator, run))
    entries.sort(key=lambda e: (-e[0], e[3]["id"], e[2]))
    return [(value, estimator, run) for _, value, estimator, run in entries[:count]]


def median(values):
    v = sorted(values)
    n = len(v)
    if n == 0:
        return math.nan
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])
