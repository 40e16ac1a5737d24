#!/usr/bin/env python3
"""Cramer-Rao bound of a GNSS receiver's time offset on a simulated drive.

Reads a run's reference.csv (t_ns, x, y, z, yaw, v: the truth the run is scored against,
docs/estimate-format.md) and prints, for the first T seconds, the smallest standard deviation
any unbiased estimator of a constant time offset d can reach from horizontal fixes at RATE Hz
with white noise SIGMA per axis, when the fix stamped t is the antenna at t - d:

    fix_k = p(t_k) - d v(t_k) + n_k,   n_k ~ N(0, sigma^2 I2)

with the track's shape known exactly (as if the lidar and the IMU made it rigid) and only its
translation (east, north) and its yaw about the centroid unknown besides d: a lower bound for
the factor graph, whose track is not exact. Fisher information F = sum_k H_k^T H_k / sigma^2,
H_k = [I2, J (p_k - c), -v_k]; the bound is sqrt((F^-1)_dd).

    python3 scripts/time_offset_crlb.py OUT/reference.csv [--sigma 1.70] [--rate 10]
"""
import argparse
import csv
import math


def inverse(m):
    n = len(m)
    a = [row[:] + [1.0 if i == j else 0.0 for j in range(n)] for i, row in enumerate(m)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(a[r][c]))
        a[c], a[p] = a[p], a[c]
        d = a[c][c]
        a[c] = [x / d for x in a[c]]
        for r in range(n):
            if r != c:
                f = a[r][c]
                a[r] = [x - f * y for x, y in zip(a[r], a[c])]
    return [row[n:] for row in a]


def bound(samples, sigma, with_yaw):
    cx = sum(s[1] for s in samples) / len(samples)
    cy = sum(s[2] for s in samples) / len(samples)
    columns = [0, 1, 2, 3] if with_yaw else [0, 1, 3]
    f = [[0.0] * len(columns) for _ in columns]
    for _, px, py, yaw, v in samples:
        vx, vy = v * math.cos(yaw), v * math.sin(yaw)
        for row in ([1.0, 0.0, -(py - cy), -vx], [0.0, 1.0, px - cx, -vy]):
            h = [row[i] for i in columns]
            for a in range(len(columns)):
                for b in range(len(columns)):
                    f[a][b] += h[a] * h[b] / sigma**2
    return math.sqrt(inverse(f)[-1][-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("reference_csv")
    parser.add_argument("--sigma", type=float, default=1.70, help="m per horizontal axis")
    parser.add_argument("--rate", type=float, default=10.0, help="fixes per second")
    parser.add_argument("--spans", default="30,60,120,240", help="first T seconds, comma list")
    args = parser.parse_args()
    with open(args.reference_csv, newline="") as f:
        truth = [(int(r["t_ns"]), float(r["x"]), float(r["y"]), float(r["yaw"]), float(r["v"]))
                 for r in csv.DictReader(f)]
    step_ns = round(1e9 / args.rate)
    fixes = [s for s in truth if s[0] % step_ns == 0]
    print("span_s,fixes,crlb_ms_translation_yaw,crlb_ms_translation")
    for span in (float(s) for s in args.spans.split(",")):
        used = [s for s in fixes if s[0] <= span * 1e9]
        if not used or used[-1][0] < (span - 1.0) * 1e9:
            continue  # the run is shorter
        print(f"{span:g},{len(used)},{1e3 * bound(used, args.sigma, True):.1f},"
              f"{1e3 * bound(used, args.sigma, False):.1f}")


if __name__ == "__main__":
    main()
