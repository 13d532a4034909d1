#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# The split by whether the small part shows: per object, the boxes of
# a results CSV split by the part's visibility at the true pose
# (part_visibility's JSON lines): "visible" (at least half of the part's
# pixels seen, and at least 20), "hidden" (fewer than 5 seen), "partly"
# (the rest). The hidden ones are split again by whether the depth can
# tell the truth from its nearest rival turn (part_visibility's rival_px:
# at least 10 pixels seen where the two differ): "hidden, told" (the part's
# absence shows: a camera's lens turned away, which its rival would show)
# and "hidden, alike" (no depth could tell: the pose should be flagged).
# For each: boxes, right at ADD <= 0.1 d, and the share the estimate
# flagged ambiguous (ihf estimate --stats-json's ambiguous_poses); with the
# report of `ihf eval --vsd --json`, also AR_VSD, the average recall by the
# visible surface (the boxes' mean vsd_share), which does not count what the
# depth cannot show.
#
#   split.py DATASET RESULTS.csv VISIBILITY.jsonl STATS.json [EVAL.json]
import csv, json, math, os, struct, sys

from part_classes import part_classes

dataset, results, visibility, stats = sys.argv[1:5]
report = sys.argv[5] if len(sys.argv) > 5 else None

def ply_vertices(path):
    with open(path, 'rb') as f:
        header = []
        while True:
            line = f.readline().decode('ascii').strip()
            header.append(line)
            if line == 'end_header':
                break
        n = next(int(l.split()[2]) for l in header if l.startswith('element vertex'))
        props = []
        in_vertex = False
        for l in header:
            if l.startswith('element'):
                in_vertex = l.startswith('element vertex')
            elif l.startswith('property') and in_vertex:
                props.append(l.split()[1])
        sizes = {'float': 4, 'float32': 4, 'double': 8, 'uchar': 1, 'uint8': 1, 'int': 4, 'uint': 4}
        stride = sum(sizes[p] for p in props)
        assert props[:3] == ['float', 'float', 'float'] or props[:3] == ['float32'] * 3, props
        data = f.read(n * stride)
        return [struct.unpack_from('<fff', data, i * stride) for i in range(n)]

info = json.load(open(os.path.join(dataset, 'models', 'models_info.json')))
models = {}
def points(obj):
    if obj not in models:
        v = ply_vertices(os.path.join(dataset, 'models', 'obj_%06d.ply' % obj))
        step = max(1, len(v) // 500)
        models[obj] = v[::step]
    return models[obj]

def apply(R, t, x):
    return [R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2] + t[i] for i in range(3)]

gt = {}
split_dir = os.path.join(dataset, 'test')
for scene in sorted(os.listdir(split_dir)):
    sg = json.load(open(os.path.join(split_dir, scene, 'scene_gt.json')))
    for im, insts in sg.items():
        for g in insts:
            gt[(int(scene), int(im), g['obj_id'])] = (g['cam_R_m2c'], g['cam_t_m2c'])

est = {}
for row in csv.DictReader(open(results)):
    key = (int(row['scene_id']), int(row['im_id']), int(row['obj_id']))
    est[key] = ([float(x) for x in row['R'].split()], [float(x) for x in row['t'].split()])

vsd_share = {}
if report:
    for e in json.load(open(report))['estimates']:
        vsd_share[(e['scene_id'], e['im_id'], e['obj_id'])] = e['vsd_share']

ambiguous = {(a['scene_id'], a['im_id'], a['obj_id']) for a in json.load(open(stats)).get('ambiguous_poses', [])}

table = {}
for line in open(visibility):
    v = json.loads(line)
    key = (v['scene_id'], v['im_id'], v['obj_id'])
    right = False
    if key in est and key in gt:
        (Re, te), (Rg, tg) = est[key], gt[key]
        add = sum(math.dist(apply(Re, te, x), apply(Rg, tg, x)) for x in points(key[2])) / len(points(key[2]))
        right = add <= 0.1 * info[str(key[2])]['diameter']
    for k in part_classes(v):
        s = table.setdefault((key[2], k), [0, 0, 0, 0.0])
        s[0] += 1
        s[1] += right
        s[2] += key in ambiguous
        s[3] += vsd_share.get(key, 0.0)

print('%-6s %-13s %6s %14s %14s' % ('object', 'part', 'boxes', 'ADD-0.1d', 'ambiguous') +
      (' %7s' % 'AR_VSD' if report else ''))
for (obj, kind), (n, right, amb, vsd) in sorted(table.items()):
    print('%-6d %-13s %6d %7d (%.3f) %7d (%.3f)' % (obj, kind, n, right, right / n, amb, amb / n) +
          (' %7.3f' % (vsd / n) if report else ''))
