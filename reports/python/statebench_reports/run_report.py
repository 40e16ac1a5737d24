"""The run report: one run folder of `statebench run` as one HTML page (docs/reports.md).

    python3 -m statebench_reports.run_report JOB.json

JOB: {"run_dir", "out", "plotly_js", "nees_bounds": {"pose": [lo, hi], "position": [lo, hi]},
"scenario": {"text", "source", "note"} (optional: else the run folder's scenario.yaml)}.
"""

import math
import os
import sys

from . import entry_point, run_figures, sumo_net
from .figures_format import fmt, percent
from .page import Page
from .run_folder import RunFolder, error_axes, read_text

# The metrics table: (row title, key path into metrics.json).
METRIC_ROWS = [
    ("epochs compared", "compared"),
    ("availability (finite estimates / IMU stamps)", "availability.fraction"),
    ("RMSE x [m]", "rmse.x_m"),
    ("RMSE y [m]", "rmse.y_m"),
    ("RMSE z [m]", "rmse.z_m"),
    ("RMSE position [m]", "rmse.position_m"),
    ("RMSE roll [rad]", "rmse.roll_rad"),
    ("RMSE pitch [rad]", "rmse.pitch_rad"),
    ("RMSE yaw [rad]", "rmse.yaw_rad"),
    ("RMSE longitudinal velocity [m/s]", "rmse.v_longitudinal_mps"),
    ("RMSE lateral velocity [m/s]", "rmse.v_lateral_mps"),
    ("APE translation RMSE [m]", "ape.translation_m.rmse"),
    ("APE translation max [m]", "ape.translation_m.max"),
    ("APE rotation RMSE [rad]", "ape.rotation_rad.rmse"),
    ("RPE translation RMSE over 10 m [m]", "rpe.translation_m.rmse"),
    ("KITTI translation error [%]", "kitti.translation_percent"),
    ("mean pose NEES (6 dof)", "nees.pose_6dof_mean"),
    ("mean position NEES (3 dof)", "nees.position_3dof_mean"),
    ("solve time p99 [ms]", "solve_ms_p99"),
]
OUTAGE_ROWS = [
    ("distance driven [m]", "distance_m"),
    ("position error at its end [m]", "error_end_m"),
    ("error at its end per distance [%]", "drift_percent_of_distance"),
    ("max position error [m]", "max_error_m"),
    ("RMSE x in it [m]", "rmse_x_m"),
    ("RMSE y in it [m]", "rmse_y_m"),
]


def _get(d, path):
    for part in path.split("."):
        if not isinstance(d, dict) or part not in d:
            return None
        d = d[part]
    return d


def _flatten(d, prefix=""):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _flatten(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _flatten(v, f"{prefix}[{i}]")
    else:
        yield prefix, d


def _header(page, run):
    s = run.summary
    page.table(["", ""], [
        ["scenario", s.get("scenario", "-")],
        ["scenario file", s.get("file", "-")],
        ["seed", s.get("seed", "-")],
        ["simulated", f"{fmt(s.get('simulated_s'))} s, {fmt(s.get('distance_m'))} m driven"],
        ["wall time", f"{fmt(s.get('wall_time_s'))} s (real-time factor {fmt(s.get('real_time_factor'))})"],
        ["estimators", ", ".join(f"{e.label} ({e.type})" for e in run.estimators)],
        ["run folder", os.path.abspath(run.dir)],
    ], text_columns=2)


def _metrics_section(page, run, outages):
    page.section("Metrics", "metrics")
    labels = [e.label for e in run.estimators]
    rows = []
    for title, path in METRIC_ROWS:
        values = [_get(e.metrics, path) for e in run.estimators]
        if all(v is None for v in values):
            continue
        rows.append([title] + [percent(v) if path == "availability.fraction" else fmt(v)
                               for v in values])
    page.table(["metric"] + labels, rows)
    for k, (begin, end) in enumerate(outages):
        page.subsection(f"GNSS outage {k + 1}: {begin:g} s to {end:g} s")
        rows = []
        for title, key in OUTAGE_ROWS:
            values = []
            for e in run.estimators:
                o = (e.metrics.get("outages") or [])
                values.append(o[k].get(key) if k < len(o) else None)
            if any(v is not None for v in values):
                rows.append([title] + [fmt(v) for v in values])
        page.table(["metric"] + labels, rows)
    all_keys = []
    for e in run.estimators:
        for key, _ in _flatten(e.metrics):
            if key not in all_keys:
                all_keys.append(key)
    flat = [dict(_flatten(e.metrics)) for e in run.estimators]
    rows = [[key] + [fmt(f.get(key)) if not isinstance(f.get(key), str) else f.get(key)
                     for f in flat] for key in all_keys]
    page.raw("<details><summary>every figure of metrics.json</summary>")
    page.table(["key"] + labels, rows)
    page.raw("</details>")


def _rejected_fixes(run, fixes):
    """Per estimator, the GNSS fixes it rejected: [(label, index, xs, ys, reasons)]."""
    if fixes is None:
        return []
    position = {(s, t): (x, y) for t, s, x, y in
                zip(fixes["t_ns"], fixes["sensor"], fixes["x"], fixes["y"])}
    out = []
    for index, e in enumerate(run.estimators):
        m = e.measurements()
        if m is None:
            continue
        xs, ys, reasons = [], [], []
        for t, s, v in zip(m["t_ns"], m["sensor"], m["verdict"]):
            if v == "accepted":
                continue
            p = position.get((s, t))
            if p:
                xs.append(p[0])
                ys.append(p[1])
                reasons.append(f"{s} {v}")
        if xs:
            out.append((e.label, index, xs, ys, reasons))
    return out


def _trajectory_section(page, run, outages, missing):
    page.section("Trajectory", "trajectory")
    lanes = None
    if run.net_file():
        lanes = sumo_net.as_trace_xy(sumo_net.lane_polylines(run.net_file()))
    else:
        missing.append("sumo/net.net.xml (the road network)")
    reference = run.reference()
    if reference is None:
        missing.append("reference.csv (the truth)")
    tracks = []
    for index, e in enumerate(run.estimators):
        track = e.estimate_track()
        if track is not None:
            tracks.append((e.label, index, track))
    fixes = run.gnss_fixes()
    by_sensor = {}
    if fixes is None:
        missing.append("gnss_fixes.csv (the GNSS fixes)")
    else:
        for t, s, x, y in zip(fixes["t_ns"], fixes["sensor"], fixes["x"], fixes["y"]):
            entry = by_sensor.setdefault(s, ([], [], []))
            entry[0].append(int(t) * 1e-9)
            entry[1].append(x)
            entry[2].append(y)
    rejected = _rejected_fixes(run, fixes)
    fig = run_figures.trajectory(lanes, reference, tracks, by_sensor, rejected, outages)
    page.figure(fig, config={"scrollZoom": True}, caption=(
        "Every estimator's real-time estimate of the IMU position and the truth over the SUMO "
        "network's lane centre lines; GNSS fixes as dots per receiver, the fixes an estimator "
        "rejected as crosses in its colour (hover: the reason); GNSS outages as a wide orange "
        "band on the truth. Scroll to zoom, drag to pan, double-click to reset."))


def _band_table(page, series, outages):
    """Fraction of epochs whose error lies inside the estimator's own +-3 sigma, per axis,
    over the run and inside the outages."""
    axes = error_axes([c for _, _, c in series])
    header = ["estimator", "epochs"] + [title for _, _, title, _ in axes]
    rows = []
    windows = [("whole run", None)] + [(f"GNSS outage {k + 1} ({b:g}-{e:g} s)", (b, e))
                                       for k, (b, e) in enumerate(outages)]
    for name, window in windows:
        for label, _, c in series:
            if window:
                idx = [i for i, t in enumerate(c["t_ns"]) if window[0] <= t <= window[1]]
            else:
                idx = range(len(c["t_ns"]))
            cells = []
            count = 0
            for error_col, sigma_col, _, _ in axes:
                errors = [c[error_col][i] for i in idx]
                sigmas = [3 * c[sigma_col][i] for i in idx]
                fraction, count = run_figures.inside_fraction(errors, [-s for s in sigmas], sigmas)
                cells.append(percent(fraction))
            rows.append([f"{label}, {name}", count] + cells)
    page.table(header, rows, text_columns=1)


def _errors_section(page, run, outages, bounds, missing):
    series = []
    for index, e in enumerate(run.estimators):
        c = e.errors()
        if c is None:
            missing.append(f"{e.label}/errors.csv")
        elif c["t_ns"]:
            series.append((e.label, index, c))
    page.section("Errors", "errors")
    if not series:
        page.note("No errors.csv in the estimators' folders: the errors against time, their "
                  "3-sigma bands and the NEES need the run details of `statebench run` "
                  "(docs/estimate-format.md, \"Run details\").")
        return
    page.figure(run_figures.errors_against_time(series, outages), caption=(
        "Estimate minus truth per axis (along and across the truth's heading; roll, pitch and "
        "yaw wrapped) and each estimator's own ±3σ from its covariance, shaded around zero: a consistent "
        "estimator's error stays inside its band about 99.7 % of the time. Drawn thinned: the "
        "errors keep each bucket's extremes, the band is each of 300 stretches at its widest; "
        "the table below counts every epoch against its own σ. A click on an estimator in the "
        "legend hides its error and band, and the axes rescale to the others."))
    page.paragraph("Epochs whose error lies inside the estimator's own ±3σ:")
    _band_table(page, series, outages)
    page.section("NEES", "nees")
    page.figure(run_figures.nees_against_time(series, bounds), caption=(
        "Normalised estimation error squared of every epoch against the estimator's covariance, "
        "with the two-sided 95 % chi-square bounds of one epoch: a consistent estimator stays "
        "between them 95 % of the time; above: over-confident, below: under-confident."))
    rows = []
    for label, _, c in series:
        cells = [label]
        for column, (low, high) in (("nees_pose", bounds["pose"]),
                                    ("nees_position", bounds["position"])):
            v = c[column]
            finite = [x for x in v if math.isfinite(x)]
            fraction, _ = run_figures.inside_fraction(v, [low] * len(v), [high] * len(v))
            cells += [fmt(sum(finite) / len(finite)) if finite else "-", percent(fraction),
                      percent(sum(1 for x in finite if x > high) / len(finite) if finite else math.nan)]
        rows.append(cells)
    page.table(["estimator", "pose NEES mean", "inside bounds", "above",
                "position NEES mean", "inside bounds", "above"], rows)


def _measurements_section(page, run, missing):
    page.section("Measurements", "measurements")
    duration = run.summary.get("simulated_s") or 0
    for index, e in enumerate(run.estimators):
        m = e.measurements()
        if m is None:
            missing.append(f"{e.label}/measurements.csv")
        elif m["t_ns"]:
            if not duration:
                duration = max(int(t) for t in m["t_ns"]) * 1e-9
            page.figure(run_figures.verdicts_over_time(e.label, m, duration), caption=(
                f"What {e.label} did with each measurement it was given, per sensor and time "
                "bin: accepted, or rejected by reason (IMU samples only when rejected). Click a "
                "legend entry to hide it."))
    rows = []
    for e in run.estimators:
        for sensor, c in sorted(((e.diagnostics or {}).get("sensors") or {}).items()):
            rejected = ", ".join(f"{k} {v}" for k, v in sorted((c.get("rejected") or {}).items()))
            events = ", ".join(f"{k} {v}" for k, v in sorted((c.get("events") or {}).items()))
            rows.append([e.label, sensor, c.get("received"), c.get("accepted"), rejected or "-",
                         c.get("downweighted"), events or "-"])
    page.paragraph("Totals (diagnostics.json):")
    page.table(["estimator", "sensor", "received", "accepted", "rejected by reason",
                "down-weighted", "events"], rows, text_columns=2)


def _solver_section(page, run):
    page.section("Solver", "solver")
    histograms, per_minute, rows = [], [], []
    for index, e in enumerate(run.estimators):
        u = (e.diagnostics or {}).get("updates") or {}
        h = u.get("solve_ms_histogram")
        if u.get("count") and h and h.get("count"):
            histograms.append((e.label, index, h))
            per_minute.append((e.label, index, u.get("per_minute") or []))
        rows.append([e.label, u.get("count", "-"), u.get("unusable", "-"),
                     fmt(u.get("mean_iterations")), fmt(u.get("solve_ms_mean")),
                     fmt(u.get("solve_ms_median")), fmt(u.get("solve_ms_p95")),
                     fmt(u.get("solve_ms_p99")), fmt(u.get("solve_ms_max"))])
    if histograms:
        page.figure(run_figures.solve_times(histograms, per_minute), caption=(
            "Wall-clock time of each solver update (optimisation, marginalisation, covariance) in "
            "bins of a tenth of a decade, and its median, p99 and maximum per minute of the run. "
            "Estimators without solver updates (filters) are left out."))
    else:
        page.note("No solve-time histogram in diagnostics.json (an estimator without solver "
                  "updates, or a run written before diagnostics.json had one).")
    page.table(["estimator", "updates", "unusable", "mean iterations", "mean [ms]", "median [ms]",
                "p95 [ms]", "p99 [ms]", "max [ms]"], rows)
    rows = []
    for e in run.estimators:
        d = e.diagnostics or {}
        rows.append([e.label, d.get("initialization", "-"), fmt(d.get("initialized_at_s")),
                     "; ".join(f"{fmt(x.get('at_s'))} s {x.get('reason')}: "
                               f"{x.get('reinitialization')} at {fmt(x.get('reinitialized_at_s'))} s"
                               for x in d.get("lost") or []) or "never"])
    page.paragraph("Initialisation and lost episodes:")
    page.table(["estimator", "initialisation", "at [s]", "lost and re-initialised"], rows,
               text_columns=2)


def _configuration_section(page, run, scenario):
    page.section("Scenario and options", "configuration")
    if scenario is None:
        text = read_text(run.file("scenario.yaml"))
        scenario = {"text": text or "", "source": run.file("scenario.yaml") if text else "",
                    "note": "" if text else "no scenario.yaml in the run folder"}
    if scenario.get("note"):
        page.note(scenario["note"])
    if scenario.get("text"):
        page.preformatted(f"scenario ({scenario.get('source')}): sensor setup and estimators "
                          "included", scenario["text"])
    for e in run.estimators:
        if e.config_text is not None:
            page.preformatted(f"options of {e.label} ({e.label}/estimator_config.yaml)",
                              e.config_text)
    faults = run.summary.get("faults")
    if faults:
        page.preformatted("injected faults (run.json)", "\n".join(str(f) for f in faults))


def build_page(run_dir, nees_bounds, scenario=None, back_link=None):
    """The run report of `run_dir` as a Page (the sweep report reuses it for its worst runs)."""
    run = RunFolder(run_dir)
    s = run.summary
    page = Page(f"Run report: {s.get('scenario', '?')} (seed {s.get('seed', '?')})",
                f"{fmt(s.get('simulated_s'))} s simulated, {fmt(s.get('distance_m'))} m, "
                f"{len(run.estimators)} estimators: {', '.join(e.label for e in run.estimators)}")
    if back_link:
        page.raw(f'<p><a href="{back_link[0]}">{back_link[1]}</a></p>')
    outages = run.outages()
    missing = []
    _header(page, run)
    notes_at = page.mark()
    _metrics_section(page, run, outages)
    _trajectory_section(page, run, outages, missing)
    _errors_section(page, run, outages, nees_bounds, missing)
    _measurements_section(page, run, missing)
    _solver_section(page, run)
    _configuration_section(page, run, scenario)
    if missing:
        page.note("Not in this run folder, so not drawn: " + ", ".join(missing) + ".",
                  at=notes_at)
    return page


def build(job):
    page = build_page(job["run_dir"], job["nees_bounds"], job.get("scenario"))
    page.write(job["out"], job["plotly_js"])


if __name__ == "__main__":
    sys.exit(entry_point.run(build, sys.argv))
