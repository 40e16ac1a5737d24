#!/usr/bin/env python3
"""What each arm of a sweep achieved against what its own covariance says it could.

For every run of a sweep store (results.db) the estimator's errors.csv gives, per axis, the RMSE
and the RMS of the reported sigma over the scored epochs. Runs are grouped by their sweep
parameters (run_parameters); each group's means over its seeds are printed, with the ratio of
every group to a reference group (e.g. the full batch) for both figures. The ratio of the RMS
sigmas is what the estimator's own model expects the ratio of the RMSEs to be: for the
real-time output against the batch, the filter-to-smoother gap of that model
(docs/batch-smoother.md, "How much lag the smoother needs").

  python3 scripts/rmse_against_sigma.py OUT/results.db fg_paper_inputs --reference batch=true

Only seeds present in every group are used. Reads the CSV files with reports/python's
statebench_reports (standard library only).
"""
import argparse
import json
import math
import os
import sqlite3
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reports",
                                "python"))
from statebench_reports.csv_columns import number, read_columns  # noqa: E402
from statebench_reports.errors import ReportInputError  # noqa: E402

AXES = ("x", "y", "yaw", "v_long")


def run_figures(errors_csv):
    """Per axis (RMSE, RMS sigma) over the rows whose error and sigma are both finite (an empty
    cell, e.g. no estimate, is NaN); a missing column or a bad cell is an error naming file:line."""
    columns = read_columns(errors_csv, {f"{kind}_{axis}": number
                                        for axis in AXES for kind in ("e", "sigma")})
    figures = {}
    for axis in AXES:
        pairs = [(e, s) for e, s in zip(columns["e_" + axis], columns["sigma_" + axis])
                 if math.isfinite(e) and math.isfinite(s)]
        if pairs:
            figures[axis] = (math.sqrt(sum(e * e for e, _ in pairs) / len(pairs)),
                             math.sqrt(sum(s * s for _, s in pairs) / len(pairs)))
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("store", help="a sweep's results.db")
    parser.add_argument("estimator", help="the estimator's name in the runs")
    parser.add_argument("--reference", default="batch=true",
                        help="axis=value naming the reference group (default batch=true)")
    args = parser.parse_args()

    ref_axis, _, ref_value = args.reference.partition("=")
    db = sqlite3.connect(args.store)
    groups = {}  # parameters (tuple of axis=value) -> seed -> figures
    for seed, parameters, run_dir, status in db.execute(
            "SELECT seed, parameters, run_dir, status FROM runs"):
        path = os.path.join(run_dir or "", args.estimator, "errors.csv")
        if status != "ok" or not os.path.exists(path):
            continue
        params = json.loads(parameters or "{}")
        key = tuple(sorted(f"{k}={v}" for k, v in params.items()))
        try:
            groups.setdefault(key, {})[seed] = run_figures(path)
        except ReportInputError as e:
            sys.exit(str(e))
    if not groups:
        sys.exit(f"{args.store}: no run of '{args.estimator}' with an errors.csv")
    seeds = sorted(set.intersection(*(set(g) for g in groups.values())))
    reference = [k for k in groups if f"{ref_axis}={ref_value}" in k]
    if len(reference) != 1:
        sys.exit(f"--reference {args.reference}: matches {len(reference)} groups, not one")
    reference = reference[0]

    def mean(key, axis, i):
        return sum(groups[key][s][axis][i] for s in seeds) / len(seeds)

    print(f"{len(seeds)} seeds in every group; reference: {' '.join(reference)}")
    print("| group | axis | RMSE | RMS sigma | RMSE / reference | sigma / reference |")
    print("|---|---|---|---|---|---|")
    for key in sorted(groups):
        for axis in AXES:
            if any(axis not in groups[key][s] or axis not in groups[reference][s] for s in seeds):
                continue
            rmse, sigma = mean(key, axis, 0), mean(key, axis, 1)
            print(f"| {' '.join(key)} | {axis} | {rmse:.4f} | {sigma:.4f} | "
                  f"{rmse / mean(reference, axis, 0):.2f} | {sigma / mean(reference, axis, 1):.2f} |")


if __name__ == "__main__":
    main()
