#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# What the wrong boxes of a results CSV got wrong (ADD > 0.1 d): the turn
# from the true pose to the estimate in the model frame. Counted per
# object: misses that are a turn about an axis within 10 deg of the
# model's x, y or z axis that slides at most 10 mm along it (a turn about
# a near-symmetry axis), and of those the half-turns (over 150 deg).
#
#   misses.py DATASET RESULTS.csv
import csv, json, math, os, struct, sys

dataset, results = sys.argv[1:3]
info = json.load(open(os.path.join(dataset, 'models', 'models_info.json')))

def vertices(obj):
    with open(os.path.join(dataset, 'models', 'obj_%06d.ply' % obj), 'rb') as f:
        header = []
        while header[-1:] != ['end_header']:
            header.append(f.readline().decode('ascii').strip())
        n = next(int(l.split()[2]) for l in header if l.startswith('element vertex'))
        props, inside = [], False
        for l in header:
            if l.startswith('element'):
                inside = l.startswith('element vertex')
            elif l.startswith('property') and inside:
                props.append(l.split()[1])
        stride = 4 * len(props)  # float properties only
        data = f.read(n * stride)
        return [struct.unpack_from('<fff', data, i * stride) for i in range(0, n, max(1, n // 500))]

def mat(R):
    return [R[0:3], R[3:6], R[6:9]]

def apply(R, t, x):
    return [sum(R[i][j] * x[j] for j in range(3)) + t[i] for i in range(3)]

gt = {}
for scene in sorted(os.listdir(os.path.join(dataset, 'test'))):
    for im, insts in json.load(open(os.path.join(dataset, 'test', scene, 'scene_gt.json'))).items():
        for g in insts:
            gt[(int(scene), int(im), g['obj_id'])] = (mat(g['cam_R_m2c']), g['cam_t_m2c'])

stats = {}
for row in csv.DictReader(open(results)):
    key = (int(row['scene_id']), int(row['im_id']), int(row['obj_id']))
    if key not in gt:
        continue
    obj = key[2]
    Re, te = mat([float(x) for x in row['R'].split()]), [float(x) for x in row['t'].split()]
    Rg, tg = gt[key]
    pts = vertices(obj)
    add = sum(math.dist(apply(Re, te, x), apply(Rg, tg, x)) for x in pts) / len(pts)
    s = stats.setdefault(obj, {'boxes': 0, 'misses': 0, 'about_axis': 0, 'half_turn': 0})
    s['boxes'] += 1
    if add <= 0.1 * info[str(obj)]['diameter']:
        continue
    s['misses'] += 1
    # Relative turn in the model frame: Rg^T Re.
    Q = [[sum(Rg[k][i] * Re[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (Q[0][0] + Q[1][1] + Q[2][2] - 1) / 2))))
    if angle > 170:
        # Near a half-turn the axis is the column of Q + I with the largest norm.
        cols = [[Q[i][j] + (i == j) for i in range(3)] for j in range(3)]
        axis = max(cols, key=lambda c: sum(v * v for v in c))
    else:
        axis = [Q[2][1] - Q[1][2], Q[0][2] - Q[2][0], Q[1][0] - Q[0][1]]
    norm = math.sqrt(sum(v * v for v in axis)) or 1.0
    alignment = max(abs(v) / norm for v in axis)
    # The estimate is the truth moved by x -> Q x + d (model frame); a turn
    # about an axis parallel to `axis` slides nothing along it.
    d = [sum(Rg[k][i] * (te[k] - tg[k]) for k in range(3)) for i in range(3)]
    slide = abs(sum(d[i] * axis[i] for i in range(3))) / norm
    if alignment >= math.cos(math.radians(10)) and slide <= 10.0:
        s['about_axis'] += 1
        s['half_turn'] += angle > 150

print('%-6s %6s %6s %22s %10s' % ('object', 'boxes', 'misses', 'turn about a model axis', 'half-turn'))
for obj, s in sorted(stats.items()):
    print('%-6d %6d %6d %22d %10d' % (obj, s['boxes'], s['misses'], s['about_axis'], s['half_turn']))
