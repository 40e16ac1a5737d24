#!/usr/bin/env python3
# Issue 14's cheap-kit checks on a sweep folder (scenarios/sweeps/car_cheap_kit.yaml): per run the
# factor graph's start (diagnostics.json) after the truth first exceeds 0.5 m/s, and the truth
# stops of 3 s or more under 0.02 m/s whose mean estimated speed from 1.5 s in is under 0.05 m/s.
#   python3 scripts/cheap_kit_checks.py out/cheap_kit
import csv, json, sys, os, glob, bisect
root = sys.argv[1]
tot_stops = ok_stops = 0; worst_init = 0.0; rows = []
for run in sorted(glob.glob(os.path.join(root, 'runs', '*'))):
    sc = json.load(open(os.path.join(run, 'run.json'))).get('scenario', '?')
    ref = list(csv.DictReader(open(os.path.join(run, 'reference.csv'))))
    t = [int(r['t_ns']) for r in ref]; v = [float(r['v']) for r in ref]
    move = next(ti for ti, vi in zip(t, v) if vi > 0.5) / 1e9
    d = json.load(open(os.path.join(run, 'factor_graph', 'diagnostics.json')))
    init_delay = d['initialized_at_s'] - move
    worst_init = max(worst_init, init_delay)
    est = list(csv.DictReader(open(os.path.join(run, 'factor_graph', 'estimate.csv'))))
    et = [int(r['t_ns']) for r in est]
    es = [(float(r['v_x'])**2 + float(r['v_y'])**2 + float(r['v_z'])**2) ** 0.5 for r in est]
    # truth stops of 3 s or more under 0.02 m/s
    i = 0; n = len(t)
    while i < n:
        if v[i] < 0.02 and t[i] / 1e9 > move:
            j = i
            while j < n and v[j] < 0.02: j += 1
            if (t[j - 1] - t[i]) / 1e9 >= 3.0 and j < n:
                a = bisect.bisect_left(et, t[i] + 1_500_000_000); b = bisect.bisect_right(et, t[j - 1])
                sp = es[a:b]
                tot_stops += 1
                if sp and sum(sp) / len(sp) < 0.05: ok_stops += 1
            i = j
        else:
            i += 1
    rows.append((sc, os.path.basename(run), d['initialization'], round(init_delay, 2)))
for r in rows: print(*r)
print('stops', ok_stops, '/', tot_stops, 'worst init delay after moving off [s]', round(worst_init, 2))
