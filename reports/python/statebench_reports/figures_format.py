"""Figures as the tables print them: four significant digits (as `results summary` and
`compare`), '-' when missing."""

import math


def fmt(value):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    if isinstance(value, int):
        return str(value)
    a = abs(value)
    if a != 0 and (a < 1e-3 or a >= 1e5):
        return f"{value:.3e}"
    return f"{value:.4g}"


def percent(fraction):
    if fraction is None or not math.isfinite(fraction):
        return "-"
    return f"{100 * fraction:.1f} %"
