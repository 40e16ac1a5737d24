"""Fewer points for long curves, so a 4-minute run at 100 Hz draws quickly in a browser.

A curve of n points keeps at most `max_points`: the stamps are cut into max_points / 2 buckets of
consecutive points and each bucket keeps its smallest and largest value (in time order), so a
spike stays visible however far the page is zoomed out. Statistics are computed on the full data,
never on what is drawn.
"""

import math


def envelope_indices(values, max_points):
    """Indices of the points to draw of `values` (NaN never chosen as an extreme)."""
    n = len(values)
    if n <= max_points:
        return list(range(n))
    buckets = max(1, max_points // 2)
    keep = []
    for b in range(buckets):
        lo = b * n // buckets
        hi = (b + 1) * n // buckets
        i_min = i_max = None
        for i in range(lo, hi):
            v = values[i]
            if v != v:  # NaN
                continue
            if i_min is None or v < values[i_min]:
                i_min = i
            if i_max is None or v > values[i_max]:
                i_max = i
        if i_min is None:
            keep.append(lo)  # all NaN: one gap marker
            continue
        keep.extend(sorted({i_min, i_max}))
    return keep


def bucket_maxima(t, values, buckets):
    """The largest finite value of each of `buckets` runs of consecutive points, at the middle
    stamp of its run: [(t, max)] (runs without a finite value left out). For a band that changes
    slowly (an estimator's sigma), drawn at its loosest in each bucket."""
    n = len(values)
    out = []
    buckets = max(1, min(buckets, n))
    for b in range(buckets):
        lo = b * n // buckets
        hi = (b + 1) * n // buckets
        finite = [v for v in values[lo:hi] if v == v]
        if hi > lo and finite:
            out.append((0.5 * (t[lo] + t[hi - 1]), max(finite)))
    return out


def stride_indices(n, max_points):
    """Every k-th index (first and last included) so that at most about max_points remain."""
    if n <= max_points:
        return list(range(n))
    step = math.ceil(n / max_points)
    indices = list(range(0, n, step))
    if indices[-1] != n - 1:
        indices.append(n - 1)
    return indices


def pick(values, indices):
    return [values[i] for i in indices]


def rounded(values, digits):
    """Values to `digits` significant digits (None for NaN, drawn by Plotly as a gap): smaller
    pages, no visible difference."""
    out = []
    for v in values:
        if v is None or v != v or v in (math.inf, -math.inf):
            out.append(None)
        elif v == 0:
            out.append(0.0)
        else:
            out.append(float(f"{v:.{digits}g}"))
    return out


def rounded_fixed(values, decimals):
    """Values rounded to `decimals` decimals (positions in m, times in s); None for NaN."""
    return [None if (v is None or v != v) else round(v, decimals) for v in values]
