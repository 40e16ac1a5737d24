"""The run report's figures (plotly.py), one function per figure; data in, go.Figure out.

Curves longer than a few thousand points are thinned for drawing (decimate.py: every bucket's
extremes kept); the statistics beside them (fractions inside bands and bounds) use every epoch.
"""

import math

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from . import decimate
from .run_folder import error_axes
from .style import (ACCEPTED_COLOUR, FIX_COLOURS, LANE_COLOUR, OUTAGE_COLOUR, REJECT_COLOURS,
                    TRUTH_COLOUR, estimator_colour, rgba)

MAX_TIME_POINTS = 1600   # per curve against time
MAX_BAND_POINTS = 300    # per sigma band (each side)
MAX_TRACK_POINTS = 4000  # per trajectory


def _shade_outages(fig, outages, rows=None):
    """Each GNSS outage as a shaded interval of the time axis (every row of a subplot grid)."""
    for begin, end in outages:
        kwargs = {"row": "all", "col": 1} if rows else {}
        fig.add_vrect(x0=begin, x1=end, fillcolor=OUTAGE_COLOUR, opacity=0.18, line_width=0,
                      layer="below", **kwargs)
    if outages:
        fig.add_annotation(x=outages[0][0], y=1.0, xref="x", yref="y domain", text=" GNSS outage",
                           showarrow=False, xanchor="left", yanchor="top",
                           font={"color": "#b36b00", "size": 11})


def trajectory(lanes_xy, reference, tracks, fixes, rejected, outages):
    """Map: lanes, the truth, each estimator's track, GNSS fixes and rejected fixes, outages.

    reference: (t, x, y) or None; tracks: [(label, index, (t, x, y))]; fixes: {sensor: (t, x, y)};
    rejected: [(label, index, xs, ys, reasons)]; outages: [(begin_s, end_s)].
    """
    fig = go.Figure()
    if lanes_xy:
        fig.add_trace(go.Scatter(x=lanes_xy[0], y=lanes_xy[1], mode="lines", name="road lanes (SUMO)",
                                 line={"color": LANE_COLOUR, "width": 1}, hoverinfo="skip"))
    if reference and outages:
        t, x, y = reference
        for k, (begin, end) in enumerate(outages):
            idx = [i for i, ti in enumerate(t) if begin <= ti <= end]
            idx = decimate.pick(idx, decimate.stride_indices(len(idx), MAX_TRACK_POINTS))
            fig.add_trace(go.Scatter(
                x=decimate.rounded_fixed(decimate.pick(x, idx), 3),
                y=decimate.rounded_fixed(decimate.pick(y, idx), 3), mode="lines",
                name="GNSS outage", legendgroup="outage", showlegend=k == 0,
                line={"color": rgba(OUTAGE_COLOUR, 0.45), "width": 12}, hoverinfo="skip"))
    for k, (sensor, (t, x, y)) in enumerate(sorted(fixes.items())):
        fig.add_trace(go.Scatter(
            x=decimate.rounded_fixed(x, 3), y=decimate.rounded_fixed(y, 3),
            customdata=decimate.rounded_fixed(t, 2), mode="markers", name=f"GNSS fixes {sensor}",
            marker={"color": FIX_COLOURS[k % len(FIX_COLOURS)], "size": 4, "opacity": 0.6},
            hovertemplate=sensor + " fix t %{customdata} s<br>x %{x} m, y %{y} m<extra></extra>"))
    if reference:
        t, x, y = reference
        idx = decimate.stride_indices(len(t), MAX_TRACK_POINTS)
        fig.add_trace(go.Scatter(
            x=decimate.rounded_fixed(decimate.pick(x, idx), 3),
            y=decimate.rounded_fixed(decimate.pick(y, idx), 3),
            customdata=decimate.rounded_fixed(decimate.pick(t, idx), 2), mode="lines",
            name="truth", line={"color": TRUTH_COLOUR, "width": 1.5},
            hovertemplate="truth t %{customdata} s<br>x %{x} m, y %{y} m<extra></extra>"))
    for label, index, (t, x, y) in tracks:
        idx = decimate.stride_indices(len(t), MAX_TRACK_POINTS)
        fig.add_trace(go.Scatter(
            x=decimate.rounded_fixed(decimate.pick(x, idx), 3),
            y=decimate.rounded_fixed(decimate.pick(y, idx), 3),
            customdata=decimate.rounded_fixed(decimate.pick(t, idx), 2), mode="lines", name=label,
            line={"color": estimator_colour(index), "width": 1.2},
            hovertemplate=label + " t %{customdata} s<br>x %{x} m, y %{y} m<extra></extra>"))
    for label, index, xs, ys, reasons in rejected:
        fig.add_trace(go.Scatter(
            x=decimate.rounded_fixed(xs, 3), y=decimate.rounded_fixed(ys, 3), text=reasons,
            mode="markers", name=f"fixes rejected by {label}",
            marker={"color": estimator_colour(index), "size": 9, "symbol": "x-thin",
                    "line": {"width": 2, "color": estimator_colour(index)}},
            hovertemplate=label + " rejected: %{text}<br>x %{x} m, y %{y} m<extra></extra>"))
    fig.update_layout(height=680, margin={"l": 60, "r": 20, "t": 30, "b": 50}, dragmode="pan",
                      legend={"orientation": "v"}, hovermode="closest")
    # First view: the drive, not the whole network (double-click zooms out to everything).
    xs, ys = [], []
    for track in ([reference] if reference else []) + [tr for _, _, tr in tracks]:
        xs += [v for v in track[1] if v == v]
        ys += [v for v in track[2] if v == v]
    if xs:
        pad = 0.05 * max(max(xs) - min(xs), max(ys) - min(ys), 20.0)
        fig.update_xaxes(range=[min(xs) - pad, max(xs) + pad])
        fig.update_yaxes(range=[min(ys) - pad, max(ys) + pad])
    fig.update_xaxes(title_text="x east [m]")
    fig.update_yaxes(title_text="y north [m]", scaleanchor="x", scaleratio=1)
    return fig


def inside_fraction(values, bounds_low, bounds_high):
    """Fraction of the finite values inside [low, high] (per-value bounds lists)."""
    inside = total = 0
    for v, lo, hi in zip(values, bounds_low, bounds_high):
        if math.isfinite(v) and math.isfinite(lo) and math.isfinite(hi):
            total += 1
            inside += lo <= v <= hi
    return (inside / total if total else math.nan), total


def errors_against_time(series, outages):
    """Error per axis against time with each estimator's +-3 sigma band.

    series: [(label, index, columns of errors.csv)]. The band is drawn at its widest over each
    of MAX_BAND_POINTS stretches of the run (sigma changes slowly; the band table beside the
    figure counts every epoch against its own sigma)."""
    axes = error_axes([c for _, _, c in series])
    titles = [f"{title} [{unit}]" for _, _, title, unit in axes]
    fig = make_subplots(rows=len(axes), cols=1, shared_xaxes=True, vertical_spacing=0.025,
                        subplot_titles=titles)
    for row, (error_col, sigma_col, _, _) in enumerate(axes, start=1):
        for label, index, c in series:
            colour = estimator_colour(index)
            band = decimate.bucket_maxima(c["t_ns"], c[sigma_col], MAX_BAND_POINTS)
            if band:
                t_band = decimate.rounded_fixed([t for t, _ in band], 2)
                upper = decimate.rounded([3 * s for _, s in band], 3)
                fig.add_trace(go.Scatter(
                    x=t_band + t_band[::-1], y=upper + [-u for u in upper[::-1]], mode="lines",
                    fill="toself", fillcolor=rgba(colour, 0.16), line={"width": 0, "color": colour},
                    name=f"{label} ±3σ", legendgroup=label, showlegend=row == 1,
                    hoverinfo="skip"), row=row, col=1)
            idx = decimate.envelope_indices(c[error_col], MAX_TIME_POINTS)
            fig.add_trace(go.Scatter(
                x=decimate.rounded_fixed(decimate.pick(c["t_ns"], idx), 2),
                y=decimate.rounded(decimate.pick(c[error_col], idx), 4), mode="lines",
                line={"width": 1, "color": colour}, name=f"{label} error", legendgroup=label,
                showlegend=row == 1,
                hovertemplate=label + " t %{x} s: %{y}<extra></extra>"), row=row, col=1)
    _shade_outages(fig, outages, rows=True)
    fig.update_layout(height=175 * len(axes) + 80, hovermode="closest",
                      margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.02, "yanchor": "bottom", "x": 0})
    fig.update_xaxes(title_text="t [s]", row=len(axes), col=1)
    for annotation in fig.layout.annotations:
        annotation.font = {"size": 12}
    return fig


def nees_against_time(series, bounds):
    """Pose (6 dof) and position (3 dof) NEES against time, log scale, with the two-sided 95 %
    chi-square bounds of one epoch. series: [(label, index, columns of errors.csv)];
    bounds: {"pose": [low, high], "position": [low, high]}."""
    rows = [("nees_pose", "pose NEES (6 dof)", bounds["pose"]),
            ("nees_position", "position NEES (3 dof)", bounds["position"])]
    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, vertical_spacing=0.08,
                        subplot_titles=[title for _, title, _ in rows])
    for r, (column, _, (low, high)) in enumerate(rows, start=1):
        for label, index, c in series:
            idx = decimate.envelope_indices(c[column], MAX_TIME_POINTS)
            values = [v if v > 0 else math.nan for v in decimate.pick(c[column], idx)]
            fig.add_trace(go.Scatter(
                x=decimate.rounded_fixed(decimate.pick(c["t_ns"], idx), 2),
                y=decimate.rounded(values, 4), mode="lines", name=label, legendgroup=label,
                showlegend=r == 1, line={"width": 1, "color": estimator_colour(index)},
                hovertemplate=label + " t %{x} s: NEES %{y}<extra></extra>"), row=r, col=1)
        for value, text in ((low, "2.5 %"), (high, "97.5 %")):
            fig.add_hline(y=value, line_dash="dash", line_color="#555", line_width=1, row=r, col=1)
            # On a log axis an annotation's y is the log10 of the value (a shape's is the value).
            axis = "" if r == 1 else str(r)
            fig.add_annotation(x=1.0, xref="x domain" if r == 1 else f"x{axis} domain",
                               y=math.log10(value), yref=f"y{axis}", text=f"χ² {text}: {value:.3g}",
                               showarrow=False, xanchor="right", yanchor="bottom",
                               font={"size": 10, "color": "#333"})
        fig.update_yaxes(type="log", title_text="NEES", row=r, col=1)
    fig.update_layout(height=620, hovermode="closest", margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.04, "yanchor": "bottom", "x": 0})
    fig.update_xaxes(title_text="t [s]", row=2, col=1)
    return fig


def _time_bin(duration_s):
    """A round bin width giving about 100 bins over the run."""
    for width in (0.5, 1, 2, 5, 10, 20, 30, 60, 120, 300):
        if duration_s / width <= 120:
            return width
    return 600


def verdicts_over_time(label, measurements, duration_s):
    """Per sensor, the measurements accepted and rejected (by reason) per time bin, stacked."""
    width = _time_bin(duration_s)
    sensors = sorted(set(measurements["sensor"]))
    verdicts = sorted(set(measurements["verdict"]) - {"accepted"})
    colour = {"accepted": ACCEPTED_COLOUR}
    for k, v in enumerate(verdicts):
        colour[v] = REJECT_COLOURS[k % len(REJECT_COLOURS)]
    counts = {}  # (sensor, verdict) -> {bin: n}
    for t_ns, sensor, verdict in zip(measurements["t_ns"], measurements["sensor"],
                                     measurements["verdict"]):
        b = int(int(t_ns) * 1e-9 // width)
        bins = counts.setdefault((sensor, verdict), {})
        bins[b] = bins.get(b, 0) + 1
    fig = make_subplots(rows=len(sensors), cols=1, shared_xaxes=True, vertical_spacing=0.04,
                        subplot_titles=[f"{label}: {s}" for s in sensors])
    shown = set()
    for r, sensor in enumerate(sensors, start=1):
        for verdict in ["accepted"] + verdicts:
            bins = counts.get((sensor, verdict))
            if not bins:
                continue
            keys = sorted(bins)
            fig.add_trace(go.Bar(
                x=[(b + 0.5) * width for b in keys], y=[bins[b] for b in keys], width=width * 0.95,
                name=verdict, legendgroup=verdict, showlegend=verdict not in shown,
                marker={"color": colour[verdict], "line": {"width": 0}},
                hovertemplate=sensor + " " + verdict + ": %{y} in %{x} s ± " + f"{width / 2:g}" +
                " s<extra></extra>"), row=r, col=1)
            shown.add(verdict)
        fig.update_yaxes(title_text="count", row=r, col=1)
    fig.update_layout(barmode="stack", height=140 * len(sensors) + 110, bargap=0,
                      margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.02, "yanchor": "bottom", "x": 0})
    fig.update_xaxes(title_text=f"t [s] (bins of {width:g} s)", row=len(sensors), col=1)
    for annotation in fig.layout.annotations:
        annotation.font = {"size": 12}
    return fig


def solve_times(histograms, per_minute):
    """Solve-time histogram of every estimator with solver updates (log time axis) and the
    per-minute median / p99 / max beside it.

    histograms: [(label, index, {"low_ms", "high_ms", "count"})];
    per_minute: [(label, index, [{"start_s", "solve_ms_median", "solve_ms_p99", ...}])]."""
    fig = make_subplots(rows=1, cols=2, column_widths=[0.55, 0.45], horizontal_spacing=0.09,
                        subplot_titles=["solve time of every update",
                                        "solve time per minute: median, p99 (dashed), max (dotted)"])
    for label, index, h in histograms:
        xs, ys = [], []
        for low, high, n in zip(h["low_ms"], h["high_ms"], h["count"]):
            xs += [low, high]
            ys += [n, n]
        xs = [xs[0]] + xs + [xs[-1]]
        ys = [0] + ys + [0]
        fig.add_trace(go.Scatter(
            x=decimate.rounded(xs, 4), y=ys, mode="lines", fill="tozeroy", name=label,
            legendgroup=label, line={"color": estimator_colour(index), "width": 1.2},
            fillcolor=rgba(estimator_colour(index), 0.25),
            hovertemplate=label + ": %{y} updates near %{x} ms<extra></extra>"), row=1, col=1)
    for label, index, periods in per_minute:
        t = [p["start_s"] for p in periods]
        for key, dash in (("solve_ms_median", "solid"), ("solve_ms_p99", "dash"),
                          ("solve_ms_max", "dot")):
            fig.add_trace(go.Scatter(
                x=t, y=[p.get(key) for p in periods], mode="lines+markers", name=f"{label} {key}",
                legendgroup=label, showlegend=False,
                line={"color": estimator_colour(index), "dash": dash, "width": 1.2},
                hovertemplate=label + " " + key[9:] + " in the minute from %{x} s: %{y} ms"
                "<extra></extra>"),
                row=1, col=2)
    fig.update_xaxes(type="log", title_text="solve time [ms]", row=1, col=1)
    fig.update_yaxes(title_text="updates", row=1, col=1)
    fig.update_xaxes(title_text="start of the minute [s]", row=1, col=2)
    fig.update_yaxes(type="log", title_text="ms", row=1, col=2)
    fig.update_layout(height=400, margin={"l": 70, "r": 20, "t": 40, "b": 50},
                      legend={"orientation": "h", "y": 1.1, "yanchor": "bottom", "x": 0})
    return fig
