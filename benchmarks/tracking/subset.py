#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Every Nth frame of a BOP dataset's scenes as a dataset of its own (depth
# files linked, not copied; ground truth, cameras and boxes filtered), so
# that a cold start every frame, which costs a full detection per box, is
# measured on a sample of a sequence's frames; `--csv` cuts a results CSV
# of the whole sequence (a tracked run) to the same frames, so both are
# scored by `ihf eval` on the same frames.
import argparse, csv, json, os, sys

ap = argparse.ArgumentParser()
ap.add_argument('--dataset', required=True)
ap.add_argument('--every', type=int, required=True)
ap.add_argument('--split', default='test')
ap.add_argument('--out', help='the subset dataset to write')
ap.add_argument('--csv', nargs=2, metavar=('IN', 'OUT'), help='cut a results CSV to the subset')
a = ap.parse_args()
keep = lambda im: int(im) % a.every == 0
if a.csv:
    with open(a.csv[0]) as f, open(a.csv[1], 'w', newline='') as g:
        r, w = csv.reader(f), csv.writer(g, lineterminator='\n')
        header = next(r)
        w.writerow(header)
        im = header.index('im_id')
        for row in r:
            if keep(row[im]):
                w.writerow(row)
    sys.exit(0)
if not a.out or os.path.exists(a.out):
    sys.exit('subset: give --out, a folder that does not exist')
src = os.path.join(a.dataset, a.split)
for name in ('camera.json',):
    os.makedirs(a.out)
    with open(os.path.join(a.dataset, name)) as f, open(os.path.join(a.out, name), 'w') as g:
        g.write(f.read())
os.symlink(os.path.abspath(os.path.join(a.dataset, 'models')), os.path.join(a.out, 'models'))
for scene in sorted(os.listdir(src)):
    d = os.path.join(a.out, a.split, scene, 'depth')
    os.makedirs(d)
    for name in ('scene_camera.json', 'scene_gt.json', 'scene_gt_info.json'):
        data = json.load(open(os.path.join(src, scene, name)))
        json.dump({k: v for k, v in data.items() if keep(k)}, open(os.path.join(a.out, a.split, scene, name), 'w'))
    for png in os.listdir(os.path.join(src, scene, 'depth')):
        if keep(os.path.splitext(png)[0]):
            os.symlink(os.path.abspath(os.path.join(src, scene, 'depth', png)), os.path.join(d, png))
boxes = [b for b in json.load(open(os.path.join(a.dataset, 'boxes.json'))) if keep(b['image_id'])]
json.dump(boxes, open(os.path.join(a.out, 'boxes.json'), 'w'))
# The boxes past each sequence's start (for ihf eval --targets): in its
# first max_defer_frames (3) frames a stream of eight new objects cannot
# detect them all inside 33 ms frames, by design.
json.dump([b for b in boxes if int(b['image_id']) >= 3], open(os.path.join(a.out, 'targets_after_start.json'), 'w'))
print(f'subset: every {a.every}th frame of {a.dataset} -> {a.out}')
