#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Given boxes from a BOP dataset's ground truth: bbox_obj (the whole
# object's box) enlarged by a factor about its centre, as a BOP detection
# list for `ihf estimate --boxes`.
import argparse, json, os, sys

ap = argparse.ArgumentParser()
ap.add_argument('--dataset', required=True)
ap.add_argument('--split', default='test')
ap.add_argument('--enlarge', type=float, default=0.10)
ap.add_argument('--out', required=True)
a = ap.parse_args()
split = os.path.join(a.dataset, a.split)
dets = []
for scene in sorted(os.listdir(split)):
    info_path = os.path.join(split, scene, 'scene_gt_info.json')
    gt_path = os.path.join(split, scene, 'scene_gt.json')
    try:
        info = json.load(open(info_path))
        gt = json.load(open(gt_path))
    except (OSError, ValueError) as e:
        sys.exit(f'gt_boxes: {e}')
    for im, insts in info.items():
        for k, inst in enumerate(insts):
            x, y, w, h = inst['bbox_obj']
            if w <= 0 or h <= 0:
                continue
            cx, cy = x + w / 2, y + h / 2
            w2, h2 = w * (1 + a.enlarge), h * (1 + a.enlarge)
            dets.append({'scene_id': int(scene), 'image_id': int(im),
                         'category_id': gt[im][k]['obj_id'], 'score': 1.0,
                         'bbox': [round(cx - w2 / 2, 1), round(cy - h2 / 2, 1), round(w2, 1), round(h2, 1)],
                         'time': 0.0})
json.dump(dets, open(a.out, 'w'), indent=1)
print(f'gt_boxes: {len(dets)} boxes -> {a.out}')
