#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Reads `ihf estimate --trace` output (JSON lines: every scored hypothesis
# and, stage "given", the ground truth scored the same way) and tells which
# stage lost each failed box:
#   ok            the best-scored hypothesis is near the truth;
#   search        the truth scores higher than every hypothesis found, so
#                 no candidate was good enough (t_ok: some candidate had the
#                 translation within 0.3 d, only the rotation was missing);
#   score         a wrong hypothesis outscores the truth (t_far: it sits
#                 more than 0.3 d away, typically on an occluder in front).
# With --replay it re-scores the traced counts with other score weights and
# counts the boxes where the truth would beat every wrong candidate: the
# ceiling of that score if the search were perfect. It replays counts only:
# with [score] residual_weight > 0 each inlier was weighted by its residual,
# which the trace does not hold, so replayed scores are the unweighted rule.
# "Near" is within 0.1 d and 15 deg, a stand-in for ADD that needs no mesh.
import argparse, itertools, json, math, sys

ap = argparse.ArgumentParser()
ap.add_argument('trace', nargs='+', help='ihf estimate --trace files')
ap.add_argument('--models-info', required=True, help="the dataset's models/models_info.json")
ap.add_argument('--replay', action='store_true', help='re-score with a grid of weights')
a = ap.parse_args()

try:
    diameters = {int(k): v['diameter'] for k, v in json.load(open(a.models_info)).items()}
except (OSError, ValueError, KeyError) as e:
    sys.exit(f'trace_report: {a.models_info}: {e}')

boxes = {}
for path in a.trace:
    try:
        lines = open(path).read().splitlines()
    except OSError as e:
        sys.exit(f'trace_report: {e}')
    for n, line in enumerate(lines, 1):
        try:
            j = json.loads(line)
        except ValueError:
            print(f'trace_report: {path}:{n}: not JSON, skipped', file=sys.stderr)
            continue
        boxes.setdefault((j['obj_id'], j['scene_id'], j['im_id']), []).append(j)


def rot_deg(a, b):
    tr = sum(a[i] * b[i] for i in range(9))
    return math.degrees(math.acos(max(-1.0, min(1.0, (tr - 1) / 2))))


HYP = ('mode', 'icp', 'view', 'view_depth', 'view_box', 'half_turn')
cases = []  # (truth, wrong hypotheses, category)
counts = {}
reach = {}  # stage -> boxes where that stage had a hypothesis near the truth
for key, rows in sorted(boxes.items()):
    truth = [j for j in rows if j['stage'] == 'given']
    hyps = [j for j in rows if j['stage'] in HYP]
    if not truth or not hyps or key[0] not in diameters:
        continue
    g, d = truth[0], diameters[key[0]]
    near = lambda j: math.dist(j['t'], g['t']) < 0.1 * d and rot_deg(j['R'], g['R']) < 15
    t_near = lambda j: math.dist(j['t'], g['t']) < 0.3 * d
    best = max(hyps, key=lambda j: j['score'])
    for stage in {j['stage'] for j in hyps if near(j)}:
        reach[stage] = reach.get(stage, 0) + 1
    if near(best):
        cat = 'ok'
    elif g['score'] > best['score']:
        cat = 'search (t_ok)' if any(t_near(j) for j in hyps) else 'search (t_far)'
    else:
        cat = 'score (t_near)' if t_near(best) else 'score (t_far)'
    counts[cat] = counts.get(cat, 0) + 1
    cases.append((g, [j for j in hyps if not near(j)]))

print(f'{len(cases)} boxes with a traced ground truth')
for cat, n in sorted(counts.items(), key=lambda x: -x[1]):
    print(f'  {cat:16s} {n:5d}  {n / max(1, len(cases)):.3f}')
print('boxes with a hypothesis near the truth, by the stage that made it:')
for stage in HYP:
    if stage in reach:
        print(f'  {stage:16s} {reach[stage]:5d}  {reach[stage] / max(1, len(cases)):.3f}')

if a.replay:
    def score(j, w_out, w_occ, box_pow):
        den = j['inliers'] + w_out * j['outliers'] + w_occ * j['occluded']
        return (j['inliers'] / den if den > 0 else 0.0) * j['box'] ** box_pow
    print('truth beats every wrong candidate (outlier weight, occluded weight, box power):')
    for w_out, w_occ, p in itertools.product((1, 2, 3, 5, 10), (0.5, 0.3, 0.2, 0.1), (1, 2)):
        n = sum(all(score(g, w_out, w_occ, p) > score(w, w_out, w_occ, p) for w in wrong)
                for g, wrong in cases)
        print(f'  {w_out:4g} {w_occ:4g} {p}: {n}/{len(cases)}')
