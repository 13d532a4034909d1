#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# How far each box's verdict lay from its line: from `ihf estimate --trace`'s
# comparison lines, the last round of a box's turns' comparison, and in it
# the distinct turn the best beat by the least. Its margin is the best's
# lead over that turn (pixels for the best less pixels for the turn) less
# the lead the verdict needed to call the pose certain (min_pixels, or half
# the informative pixels if more): at or above 0 every turn was beaten and
# the pose is certain; below, it is flagged ambiguous. Per object and
# part visibility (split.py's classes): boxes, flagged, the margin's 10th,
# 50th and 90th percentiles, and how many lie within 10 pixels of the line.
#
#   margins.py TRACE.jsonl VISIBILITY.jsonl
import collections, json, math, sys

from part_classes import part_classes

trace, visibility = sys.argv[1:3]

# The finest class of each box.
kind = {}
for line in open(visibility):
    v = json.loads(line)
    kind[(v['scene_id'], v['im_id'], v['obj_id'])] = part_classes(v)[-1]

last, flagged = {}, {}
for line in open(trace):
    if '"comparison"' not in line and '"result"' not in line:
        continue
    d = json.loads(line)
    key = (d['scene_id'], d['im_id'], d['obj_id'])
    if d['stage'] == 'result':
        flagged[key] = d['ambiguous']
        continue
    if d['kind'] != 'turn':
        continue
    r = last.setdefault(key, [-1, []])
    if d['round'] > r[0]:
        r[0], r[1] = d['round'], []
    if d['distinct'] and not d['reported']:
        r[1].append(d)

table = collections.defaultdict(list)
for key, (_, turns) in last.items():
    if not turns or key not in kind:
        continue
    margin = min(t['for_best'] - t['for_rival'] - max(t['min_pixels'], math.ceil(0.5 * t['informative']))
                 for t in turns)
    table[(key[2], kind[key])].append((margin, flagged.get(key, False)))

print('%-6s %-13s %5s %7s %17s %10s' % ('object', 'part', 'boxes', 'flagged', 'margin p10/50/90', 'within 10'))
for (obj, k), rows in sorted(table.items()):
    m = sorted(x[0] for x in rows)
    print('%-6d %-13s %5d %7d %17s %10d' % (obj, k, len(m), sum(x[1] for x in rows),
                                          '%d / %d / %d' % (m[len(m) // 10], m[len(m) // 2], m[9 * len(m) // 10]),
                                          sum(1 for x in m if abs(x) <= 10)))
