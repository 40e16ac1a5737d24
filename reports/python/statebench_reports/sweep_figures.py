"""The sweep report's figures: per metric the runs of every cell (strip plot and CDF), and the
ANEES of every cell against its chi-square bounds."""

import hashlib
import math

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from .sweep_cells import cell_label, cell_values, median
from .style import estimator_colour

DASHES = ["solid", "dash", "dot", "dashdot", "longdash", "longdashdot"]


def _jitter(run_id, width):
    """A fixed offset per run (from its id), so a page drawn twice looks the same."""
    h = int(hashlib.sha256(run_id.encode()).hexdigest()[:8], 16) / 0xFFFFFFFF
    return (h - 0.5) * width


def _positions(data):
    values = cell_values(data)
    estimators = data["estimators"]
    step = 0.8 / max(len(estimators), 1)
    offset = {e: (k - (len(estimators) - 1) / 2) * step for k, e in enumerate(estimators)}
    index = {v: i for i, v in enumerate(values)}
    return values, index, offset, step


def metric_distribution(data, cells, metric, links):
    """Left: every run's value per cell and estimator (hover: run; click: its report when it
    has one) with the cell's median; right: the empirical CDF of each cell and estimator."""
    values, index, offset, step = _positions(data)
    fig = make_subplots(rows=1, cols=2, column_widths=[0.5, 0.5], horizontal_spacing=0.08,
                        subplot_titles=["every run (bar: median)", "cumulative distribution"])
    for k, estimator in enumerate(data["estimators"]):
        colour = estimator_colour(k)
        xs, ys, custom, mx, my = [], [], [], [], []
        for value in values:
            cell = cells[(estimator, value)]
            entries = cell.values.get(metric, [])
            for v, run in entries:
                xs.append(index[value] + offset[estimator] + _jitter(run["id"], step * 0.6))
                ys.append(v)
                params = ", ".join(f"{a}={b}" for a, b in sorted(run["parameters"].items()))
                custom.append([run["id"], run["seed"], params, links.get(run["id"], "")])
            if entries:
                mx.append(index[value] + offset[estimator])
                my.append(median([v for v, _ in entries]))
        fig.add_trace(go.Scatter(
            x=xs, y=ys, customdata=custom, mode="markers", name=estimator, legendgroup=estimator,
            marker={"color": colour, "size": 6, "opacity": 0.75},
            hovertemplate=("run %{customdata[0]} seed %{customdata[1]}<br>%{customdata[2]}<br>"
                           + metric + " = %{y}<extra>" + estimator + "</extra>")), row=1, col=1)
        fig.add_trace(go.Scatter(
            x=mx, y=my, mode="markers", name=f"{estimator} median", legendgroup=estimator,
            showlegend=False, marker={"symbol": "line-ew", "size": 26, "color": colour,
                                      "line": {"width": 3, "color": colour}},
            hovertemplate="median %{y}<extra>" + estimator + "</extra>"), row=1, col=1)
        for c, value in enumerate(values):
            entries = sorted(v for v, _ in cells[(estimator, value)].values.get(metric, []))
            if not entries:
                continue
            n = len(entries)
            cx, cy = [entries[0]], [0.0]
            for i, v in enumerate(entries):
                cx += [v, v]
                cy += [i / n, (i + 1) / n]
            fig.add_trace(go.Scatter(
                x=cx, y=cy, mode="lines", name=f"{estimator}, {cell_label(data, value)}",
                legendgroup=estimator, showlegend=False,
                line={"color": colour, "dash": DASHES[c % len(DASHES)], "width": 1.5},
                hovertemplate=(estimator + ", " + cell_label(data, value) +
                               ": %{y:.0%} of runs ≤ %{x}<extra></extra>")), row=1, col=2)
    fig.update_xaxes(tickvals=list(range(len(values))),
                     ticktext=[str(v) if data["by"] else "all runs" for v in values],
                     title_text=data["by"] or "", row=1, col=1)
    # Values over more than two decades (a diverged run among good ones): log scale.
    every = [v for cell in cells.values() for v, _ in cell.values.get(metric, [])]
    scale = "log" if every and min(every) > 0 and max(every) / min(every) > 100 else "linear"
    fig.update_yaxes(title_text=metric, type=scale, row=1, col=1)
    fig.update_xaxes(title_text=metric, type=scale, row=1, col=2)
    fig.update_yaxes(title_text="fraction of runs", range=[0, 1.02], row=1, col=2)
    fig.update_layout(height=420, hovermode="closest", margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.08, "yanchor": "bottom", "x": 0})
    return fig


def anees(data, cells, metric):
    """The ANEES (mean NEES over the cell's runs) of every cell and estimator, with the
    two-sided 95 % chi-square bounds for that many runs as a grey bar."""
    values, index, offset, step = _positions(data)
    bounds = data["nees_bounds"][metric]["by_runs"]
    fig = go.Figure()
    for k, estimator in enumerate(data["estimators"]):
        xs, ys, texts, bx, bmid, bup, bdown = [], [], [], [], [], [], []
        for value in values:
            entries = [v for v, _ in cells[(estimator, value)].values.get(metric, [])]
            if not entries:
                continue
            n = len(entries)
            a = sum(entries) / n
            low, high = bounds[min(n, len(bounds)) - 1]
            x = index[value] + offset[estimator]
            xs.append(x)
            ys.append(a)
            texts.append(f"{n} runs, bounds [{low:.3g}, {high:.3g}]")
            mid = math.sqrt(low * high)
            bx.append(x)
            bmid.append(mid)
            bup.append(high - mid)
            bdown.append(mid - low)
        fig.add_trace(go.Scatter(
            x=bx, y=bmid, mode="markers", marker={"size": 0.1, "color": "rgba(0,0,0,0)"},
            error_y={"type": "data", "array": bup, "arrayminus": bdown, "color": "#999",
                     "thickness": 10, "width": 0}, name="95 % bounds", legendgroup="bounds",
            showlegend=k == 0, hoverinfo="skip"))
        fig.add_trace(go.Scatter(
            x=xs, y=ys, text=texts, mode="markers", name=estimator,
            marker={"color": estimator_colour(k), "size": 11, "symbol": "diamond"},
            hovertemplate="ANEES %{y:.3g}<br>%{text}<extra>" + estimator + "</extra>"))
    fig.update_xaxes(tickvals=list(range(len(values))),
                     ticktext=[str(v) if data["by"] else "all runs" for v in values],
                     title_text=data["by"] or "")
    fig.update_yaxes(type="log", title_text=f"ANEES ({metric})")
    fig.update_layout(height=380, hovermode="closest", margin={"l": 70, "r": 20, "t": 30, "b": 50},
                      legend={"orientation": "h", "y": 1.02, "yanchor": "bottom", "x": 0})
    return fig
