#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Per frame of a stream: how many of its ground-truth objects `ihf eval`
# found correct (ADD/ADI error under 0.1 of the diameter), from the
# evaluation JSON (`ihf eval --json`). Prints the counts frame by frame and
# the least count from frame --from on.
import argparse, collections, json

ap = argparse.ArgumentParser()
ap.add_argument('eval_json')
ap.add_argument('--from', dest='first', type=int, default=0)
a = ap.parse_args()
rep = json.load(open(a.eval_json))
diam = {o['obj_id']: o['diameter'] for o in rep['objects']}
right = collections.Counter()
frames = set()
for e in rep['estimates']:
    frames.add((e['scene_id'], e['im_id']))
    if e['matched'] and e['error_mm'] is not None and e['error_mm'] < 0.1 * diam[e['obj_id']]:
        right[(e['scene_id'], e['im_id'])] += 1
counts = [right[f] for f in sorted(frames)]
print('right per frame:', ' '.join(str(c) for c in counts))
tail = counts[a.first:]
print(f'from frame {a.first}: least {min(tail) if tail else 0}, most {max(tail) if tail else 0} right')
