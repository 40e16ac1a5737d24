"""Colours shared by every report: one per estimator (in run.json's order), the truth in black."""

ESTIMATOR_COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
                     "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"]
TRUTH_COLOUR = "#111111"
LANE_COLOUR = "#c5cad3"
OUTAGE_COLOUR = "#ff9f1c"
ACCEPTED_COLOUR = "#8cc084"
REJECT_COLOURS = ["#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
                  "#7f7f7f"]
FIX_COLOURS = ["#6c8ebf", "#82b366", "#b85450", "#9673a6"]


def estimator_colour(index):
    return ESTIMATOR_COLOURS[index % len(ESTIMATOR_COLOURS)]


def rgba(hex_colour, alpha):
    h = hex_colour.lstrip("#")
    r, g, b = int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16)
    return f"rgba({r},{g},{b},{alpha})"
