#!/usr/bin/env python3
# Per rotation axis NEES of an estimate against a recorded log's truth (errors.csv has yaw only):
# e = 2 vec(q_true^-1 q_est), the right perturbation in the IMU frame as estimate.csv's var_rot_*
# is defined (docs/estimate-format.md), truth from truth.csv's IMU columns (the IMU as mounted).
# Prints the mean of e_k^2 / var_rot_k per axis (roll, pitch, yaw for an IMU aligned with the
# body; ideal 1) and each axis' mean and RMS error, over every STEP-th estimate (default 10)
# whose stamp is a truth sample. docs/calibration-states.md, "Setup 1 per rotation axis".
#   statebench record SCENARIO --seed S --duration D --out LOG
#   statebench estimate LOG --out EST [--config FILE]
#   python3 scripts/attitude_nees.py LOG EST [STEP]
import csv
import math
import sys


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: attitude_nees.py LOG_DIR ESTIMATE_DIR [STEP]")
    log, est = sys.argv[1], sys.argv[2]
    step = int(sys.argv[3]) if len(sys.argv) == 4 else 10
    truth = {}
    with open(log + "/truth.csv") as f:
        rows = csv.reader(f)
        header = next(rows)
        qi, ti = header.index("q_world_imu_w"), header.index("t_ns")
        for row in rows:
            truth[int(row[ti])] = tuple(float(row[qi + j]) for j in range(4))
    nees, errors = [0.0] * 3, [[], [], []]
    with open(est + "/estimate.csv") as f:
        for k, row in enumerate(csv.DictReader(f)):
            if k % step:
                continue
            t = int(row["t_ns"])
            if t not in truth or row["status"] != "global":
                continue
            q_true = truth[t]
            q_est = tuple(float(row[c]) for c in ("q_w", "q_x", "q_y", "q_z"))
            dq = qmul((q_true[0], -q_true[1], -q_true[2], -q_true[3]), q_est)
            if dq[0] < 0:
                dq = tuple(-x for x in dq)
            for a, axis in enumerate("xyz"):
                e = 2.0 * dq[1 + a]
                nees[a] += e * e / float(row["var_rot_" + axis])
                errors[a].append(e)
    n = len(errors[0])
    if n == 0:
        sys.exit("no estimate at a truth stamp")
    print("estimates %d" % n)
    for a, name in enumerate(("x (roll)", "y (pitch)", "z (yaw)")):
        e = errors[a]
        print("%-10s NEES %.2f  mean error %+.2f mrad  RMS %.2f mrad" %
              (name, nees[a] / n, 1e3 * sum(e) / n, 1e3 * math.sqrt(sum(x * x for x in e) / n)))


if __name__ == "__main__":
    main()
