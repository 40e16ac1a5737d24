"""The sweep report: a sweep's results store as one HTML page, with the worst runs' own run
reports alongside (docs/reports.md).

    python3 -m statebench_reports.sweep_report JOB.json

JOB: {"out", "plotly_js", "data": SweepReportData (reports/sweep_report_data.hpp), "worst": N,
"nees_bounds": one epoch's bounds, for the run reports}. The run reports go to
<out without .html>_runs/<run id>.html.
"""

import os
import sys

from . import entry_point, run_report, sweep_cells, sweep_figures
from .errors import ReportInputError
from .figures_format import fmt, percent
from .page import Page, escape


def _anees_verdict(a, low, high):
    if a > high:
        return "over-confident"
    if a < low:
        return "under-confident"
    return "consistent"


def _overview(page, data, cells):
    runs = data["runs"]
    failed = sum(1 for r in runs if r["status"] != "ok")
    sweeps = data["sweeps"]
    page.table(["", ""], [
        ["store", data["store"]],
        ["sweeps", "; ".join(f"{s['name']} ({s['file']}, {s['code_version']}, {s['host']}"
                             f"{', shard ' + s['shard'] if s['shard'] else ''}, {s['started_at']})"
                             for s in sweeps) or "-"],
        ["runs", f"{len(runs)}: {len(runs) - failed} ok, {failed} failed"],
        ["axes", ", ".join(data["axes"]) or "-"],
        ["cells by", data["by"] or "(none: all runs)"],
        ["estimators", ", ".join(data["estimators"]) or "-"],
    ], text_columns=2)
    page.section("Summary", "summary")
    header = ["estimator", "cell", "runs", "failed", "no estimate"] + \
        [f"{m} median" for m in data["metrics"]]
    rows = []
    for (estimator, value), cell in cells.items():
        row = [estimator, sweep_cells.cell_label(data, value), cell.runs, cell.failed,
               cell.no_estimate]
        for m in data["metrics"]:
            v = sweep_cells.median([x for x, _ in cell.values.get(m, [])])
            row.append(percent(v) if m == "availability.fraction" else fmt(v))
        rows.append(row)
    page.table(header, rows, text_columns=2)


def _anees_section(page, data, cells):
    for metric, bounds in data["nees_bounds"].items():
        page.section(f"ANEES: {metric}", "anees-" + metric.replace(".", "-"))
        page.figure(sweep_figures.anees(data, cells, metric), caption=(
            f"The mean of {metric} over each cell's runs (ANEES) and its two-sided 95 % "
            f"chi-square bounds for that many runs of a {bounds['dof']:g}-dof NEES "
            "[chi2(0.025, N dof)/N, chi2(0.975, N dof)/N]: a consistent estimator's ANEES falls "
            "inside the grey bar. Each run's figure is itself a mean over its epochs, so these "
            "bounds are the lenient ones."))
        rows = []
        for (estimator, value), cell in cells.items():
            entries = [v for v, _ in cell.values.get(metric, [])]
            if not entries:
                rows.append([estimator, sweep_cells.cell_label(data, value), 0, "-", "-", "-"])
                continue
            n = len(entries)
            a = sum(entries) / n
            low, high = bounds["by_runs"][min(n, len(bounds["by_runs"])) - 1]
            rows.append([estimator, sweep_cells.cell_label(data, value), n, fmt(a),
                         f"[{fmt(low)}, {fmt(high)}]", _anees_verdict(a, low, high)])
        page.table(["estimator", "cell", "runs", "ANEES", "95 % bounds", ""], rows,
                   text_columns=2)


def _failed_section(page, data):
    page.section("Failed runs", "failed")
    failed = [r for r in data["runs"] if r["status"] != "ok"]
    if not failed:
        page.paragraph("None: every run of the store succeeded.")
        return
    rows = []
    for r in failed:
        params = ", ".join(f"{a}={b}" for a, b in sorted(r["parameters"].items()))
        rows.append([r["id"], r["scenario"], r["seed"], params or "-", r["exit_code"],
                     f"<pre>{escape(r['error'] or '-')}</pre>", r["run_dir"]])
    page.table(["run", "scenario", "seed", "parameters", "exit code", "error", "folder"], rows,
               text_columns=4, markup_columns=(5,), row_classes=["failed"] * len(rows))


def _worst_section(page, data, cells, count, links):
    page.section("Worst runs", "worst")
    page.paragraph(f"The {count} worst runs of each metric over every cell and estimator "
                   "(errors: the largest; NEES: the farthest from its degrees of freedom on a "
                   "log scale; availability: the lowest), each linked to its own run report.")
    rows = []
    for metric in data["metrics"]:
        for value, estimator, run in sweep_cells.worst_runs(data, cells, metric, count):
            params = ", ".join(f"{a}={b}" for a, b in sorted(run["parameters"].items()))
            link = links.get(run["id"])
            run_cell = (f'<a href="{escape(link)}">{escape(run["id"])}</a>' if link
                        else escape(run["id"]) + " (no run folder)")
            rows.append([metric, estimator, fmt(value), run_cell, run["seed"], params or "-"])
    page.table(["metric", "estimator", "value", "run report", "seed", "parameters"], rows,
               text_columns=2, markup_columns=(3,))


def _run_reports(job, data, cells, out):
    """Writes the run report of every worst run that has a run folder; {run id: relative link}."""
    stem = os.path.splitext(os.path.basename(out))[0]
    folder_name = f"{stem}_runs"
    folder = os.path.join(os.path.dirname(os.path.abspath(out)), folder_name)
    chosen = []
    for metric in data["metrics"]:
        for _, _, run in sweep_cells.worst_runs(data, cells, metric, job.get("worst", 3)):
            if run["id"] not in [r["id"] for r in chosen]:
                chosen.append(run)
    links = {}
    for run in chosen:
        run_dir = run.get("run_dir") or ""
        if not os.path.isfile(os.path.join(run_dir, "run.json")):
            continue
        try:
            page = run_report.build_page(run_dir, job["nees_bounds"],
                                         back_link=(f"../{os.path.basename(out)}",
                                                    "back to the sweep report"))
        except ReportInputError as e:
            raise ReportInputError(f"run {run['id']}: {e}") from None
        page.write(os.path.join(folder, f"{run['id']}.html"), job["plotly_js"])
        links[run["id"]] = f"{folder_name}/{run['id']}.html"
    return links


def build(job):
    data = job["data"]
    out = job["out"]
    cells = sweep_cells.split(data)
    names = ", ".join(sorted({s["name"] for s in data["sweeps"]})) or os.path.basename(data["store"])
    page = Page(f"Sweep report: {names}",
                f"{len(data['runs'])} runs, cells by {data['by'] or '(none)'}")
    if not data["runs"]:
        raise ReportInputError(f"{data['store']}: the store holds no run")
    links = _run_reports(job, data, cells, out)
    _overview(page, data, cells)
    for metric in data["metrics"]:
        if not any(cell.values.get(metric) for cell in cells.values()):
            continue
        page.section(metric, "metric-" + metric.replace(".", "-").replace("[", "").replace("]", ""))
        page.figure(sweep_figures.metric_distribution(data, cells, metric, links), caption=(
            f"{metric} of every run with an estimate, per cell and estimator (a click on a run "
            "with a report opens it), and the cumulative distribution of each cell (line style: "
            "cell)."))
    _anees_section(page, data, cells)
    _failed_section(page, data)
    _worst_section(page, data, cells, job.get("worst", 3), links)
    page.write(out, job["plotly_js"])


if __name__ == "__main__":
    sys.exit(entry_point.run(build, sys.argv))
