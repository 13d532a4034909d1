#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# A still stream from one BOP image: the image repeated as frames 0..N-1 of
# one scene (depth files linked, not copied), with its ground truth, so a
# tracker can be run and scored on it by `ihf estimate --sequence` and
# `ihf eval`. The detector's boxes come from benchmarks/accuracy/gt_boxes.py.
import argparse, json, os, shutil, sys

ap = argparse.ArgumentParser()
ap.add_argument('--dataset', required=True)
ap.add_argument('--split', default='test')
ap.add_argument('--scene', type=int, required=True)
ap.add_argument('--image', type=int, required=True)
ap.add_argument('--frames', type=int, default=30)
ap.add_argument('--out', required=True)
a = ap.parse_args()
src = os.path.join(a.dataset, a.split, f'{a.scene:06d}')
dst = os.path.join(a.out, a.split, f'{a.scene:06d}')
if os.path.exists(a.out):
    sys.exit(f'still_stream: {a.out} exists')
os.makedirs(os.path.join(dst, 'depth'))
for f in ('camera.json',):
    shutil.copy(os.path.join(a.dataset, f), os.path.join(a.out, f))
os.symlink(os.path.abspath(os.path.join(a.dataset, 'models')), os.path.join(a.out, 'models'))
key = str(a.image)
for name in ('scene_camera.json', 'scene_gt.json', 'scene_gt_info.json'):
    try:
        data = json.load(open(os.path.join(src, name)))
    except (OSError, ValueError) as e:
        sys.exit(f'still_stream: {e}')
    if key not in data:
        sys.exit(f'still_stream: {name} has no image {a.image}')
    json.dump({str(i): data[key] for i in range(a.frames)}, open(os.path.join(dst, name), 'w'))
depth = os.path.abspath(os.path.join(src, 'depth', f'{a.image:06d}.png'))
for i in range(a.frames):
    os.symlink(depth, os.path.join(dst, 'depth', f'{i:06d}.png'))
print(f'still_stream: scene {a.scene} image {a.image} as {a.frames} frames -> {a.out}')
