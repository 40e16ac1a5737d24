"""The compare report: a regression comparison of two stores or run folders as one HTML page
(docs/regression.md, docs/reports.md).

    python3 -m statebench_reports.compare_report JOB.json

JOB: {"out", "plotly_js", "comparison": ComparisonJson (reports/comparison_json.hpp)}.
"""

import hashlib
import sys

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from . import entry_point
from .figures_format import fmt
from .page import Page
from .style import estimator_colour

VERDICT_COLOURS = {"worse": "#d62728", "better": "#2ca02c", "no significant change": "#7f7f7f",
                   "no data": "#cccccc"}


def _jitter(key, width):
    h = int(hashlib.sha256(key.encode()).hexdigest()[:8], 16) / 0xFFFFFFFF
    return (h - 0.5) * width


def _difference_label(m):
    if m["better"] == "closer":
        return f"|candidate - {fmt(m['target'])}| - |base - {fmt(m['target'])}|"
    return "candidate - base"


def metric_figure(metric, rows, estimators):
    """Left: the paired differences of each estimator (one dot per pair, hover: the pair), their
    median with its 95 % bootstrap interval and the band of changes below the threshold;
    right: candidate against base per pair, with the line of no change."""
    fig = make_subplots(rows=1, cols=2, column_widths=[0.55, 0.45], horizontal_spacing=0.1,
                        subplot_titles=[f"paired differences ({_difference_label(rows[0])})",
                                        "candidate against base, per pair"])
    index = {e: i for i, e in enumerate(estimators)}
    low_all, high_all = [], []
    for m in rows:
        i = index[m["estimator"]]
        colour = estimator_colour(i)
        pairs = m["paired"]
        if m["threshold"] is not None and m["pairs"]:
            fig.add_shape(type="rect", x0=i - 0.4, x1=i + 0.4, y0=-m["threshold"],
                          y1=m["threshold"], fillcolor="#e8e8e8", line_width=0, layer="below",
                          row=1, col=1)
        fig.add_trace(go.Scatter(
            x=[i + _jitter(p["key"], 0.5) for p in pairs], y=[p["difference"] for p in pairs],
            customdata=[[p["key"], p["base"], p["candidate"]] for p in pairs], mode="markers",
            name=m["estimator"], legendgroup=m["estimator"],
            marker={"color": colour, "size": 7, "opacity": 0.75},
            hovertemplate=("%{customdata[0]}<br>base %{customdata[1]}, candidate "
                           "%{customdata[2]}<br>difference %{y}<extra>" + m["estimator"] +
                           "</extra>")), row=1, col=1)
        interval = m["difference_interval"]
        if m["median_difference"] is not None and None not in interval:
            fig.add_trace(go.Scatter(
                x=[i], y=[m["median_difference"]], mode="markers", legendgroup=m["estimator"],
                showlegend=False, name=f"{m['estimator']} median",
                marker={"symbol": "diamond", "size": 13,
                        "color": VERDICT_COLOURS.get(m["verdict"], "#000"),
                        "line": {"color": "#222", "width": 1}},
                error_y={"type": "data", "symmetric": False,
                         "array": [interval[1] - m["median_difference"]],
                         "arrayminus": [m["median_difference"] - interval[0]],
                         "color": "#222", "thickness": 1.5, "width": 8},
                hovertemplate=(f"median difference %{{y}}<br>95 % interval [{fmt(interval[0])}, "
                               f"{fmt(interval[1])}]<br>p = {fmt(m['p_value'])}, threshold "
                               f"±{fmt(m['threshold'])}<br>{m['verdict']}<extra>"
                               f"{m['estimator']}</extra>")), row=1, col=1)
        bases = [p["base"] for p in pairs]
        candidates = [p["candidate"] for p in pairs]
        low_all += [v for v in bases + candidates if v is not None]
        high_all += [v for v in bases + candidates if v is not None]
        fig.add_trace(go.Scatter(
            x=bases, y=candidates, customdata=[p["key"] for p in pairs], mode="markers",
            legendgroup=m["estimator"], showlegend=False, name=m["estimator"],
            marker={"color": colour, "size": 7, "opacity": 0.75},
            hovertemplate=("%{customdata}<br>base %{x}, candidate %{y}<extra>" + m["estimator"] +
                           "</extra>")), row=1, col=2)
    if low_all:
        lo, hi = min(low_all), max(high_all)
        fig.add_trace(go.Scatter(x=[lo, hi], y=[lo, hi], mode="lines", name="no change",
                                 line={"color": "#888", "dash": "dash", "width": 1},
                                 hoverinfo="skip"), row=1, col=2)
    fig.add_hline(y=0, line_color="#555", line_width=1, row=1, col=1)
    fig.update_xaxes(tickvals=list(range(len(estimators))), ticktext=estimators,
                     range=[-0.6, len(estimators) - 0.4], row=1, col=1)
    fig.update_yaxes(title_text=f"difference of {metric}", row=1, col=1)
    fig.update_xaxes(title_text=f"base {metric}", row=1, col=2)
    fig.update_yaxes(title_text=f"candidate {metric}", row=1, col=2)
    fig.update_layout(height=400, hovermode="closest", margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.08, "yanchor": "bottom", "x": 0})
    return fig


def build(job):
    c = job["comparison"]
    worse = sum(1 for m in c["metrics"] if m["verdict"] == "worse")
    better = sum(1 for m in c["metrics"] if m["verdict"] == "better")
    page = Page("StateBench comparison: " + ("REGRESSION" if worse else "no regression"),
                f"base {c['base']['name']} ({c['base']['runs']} runs) vs candidate "
                f"{c['candidate']['name']} ({c['candidate']['runs']} runs): {c['pairs']} pairs; "
                f"{worse} worse, {better} better")
    page.section("Verdicts", "verdicts")
    page.paragraph(f"Runs paired by scenario, parameters and seed. Per estimator and metric: "
                   f"medians, the median of the paired differences with its 95 % bootstrap "
                   f"interval, the two-sided Wilcoxon signed-rank p-value and the verdict "
                   f"against the threshold (significance {c['significance']:g}; "
                   f"docs/regression.md).")
    rows, classes = [], []
    for m in c["metrics"]:
        interval = m["difference_interval"]
        rows.append([m["estimator"], m["metric"], m["pairs"], fmt(m["base_median"]),
                     fmt(m["candidate_median"]), fmt(m["median_difference"]),
                     f"[{fmt(interval[0])}, {fmt(interval[1])}]", fmt(m["p_value"]),
                     fmt(m["threshold"]), m["verdict"]])
        classes.append(m["verdict"] if m["verdict"] in ("worse", "better") else "")
    page.table(["estimator", "metric", "pairs", "base median", "candidate median", "median diff",
                "95% CI of diff", "p (signed-rank)", "threshold", "verdict"], rows,
               text_columns=2, row_classes=classes)
    estimators = sorted({m["estimator"] for m in c["metrics"]})
    page.section("Paired differences", "differences")
    for metric in dict.fromkeys(m["metric"] for m in c["metrics"]):
        rows = [m for m in c["metrics"] if m["metric"] == metric and m["pairs"]]
        page.subsection(metric)
        if not rows:
            page.note(f"{metric}: no pair where both sides have a finite value.")
            continue
        page.figure(metric_figure(metric, rows, estimators), caption=(
            "Each dot a pair of runs (same scenario, parameters and seed); the diamond is the "
            "median difference coloured by its verdict (red worse, green better, grey no "
            "significant change) with its 95 % bootstrap interval; the grey band: changes "
            "smaller than the threshold, never a verdict."))
    if c["unpaired"]:
        page.section("Runs without a partner", "unpaired")
        page.preformatted(f"{len(c['unpaired'])} runs found on one side only (left out)",
                          "\n".join(c["unpaired"]), open_=True)
    page.write(job["out"], job["plotly_js"])


if __name__ == "__main__":
    sys.exit(entry_point.run(build, sys.argv))
