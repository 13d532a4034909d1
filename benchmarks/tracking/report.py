#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# One line of results for a run of benchmarks/tracking/run.sh: mean F1 and
# ADD-0.1d recall from `ihf eval --json`; from `ihf estimate`'s log the
# boxes answered by tracking, the tracked and detected boxes' latency and
# the frames' (median, p99, overruns); and with the sequences' events
# (sequences.json of `ihf synth --sequence`) how many frames after each
# move or put-down ended the object's pose was right again (error under
# 0.1 of its diameter).
import argparse, collections, json, re

ap = argparse.ArgumentParser()
ap.add_argument('name')
ap.add_argument('eval_json')
ap.add_argument('log')
ap.add_argument('--sequences')
a = ap.parse_args()
rep = json.load(open(a.eval_json))
log = open(a.log).read()

def find(pattern, default='-'):
    m = re.search(pattern, log)
    return m.groups() if m else None

parts = [a.name, f"F1 {rep['mean']['mean_f1']:.4f}", f"recall {rep['mean']['recall_0.1d']:.4f}"]
boxes = find(r'(\d+) boxes, (\d+) poses')
if boxes:
    parts.append(f'boxes {boxes[0]}')
t = find(r'tracking: (\d+) tracked, (\d+) detected \((\d+) re-detected\), (\d+) deferred \((\d+) provisional\), '
         r'(\d+) duplicate.*?'
         r'tracked box median ([\d.]+) ms p99 ([\d.]+) ms; detected box median ([\d.]+) ms p99 ([\d.]+) ms; '
         r'frame overruns (\d+)')
if t:
    tracked, detected = int(t[0]), int(t[1])
    parts += [f'tracked {tracked / max(1, tracked + detected):.3f}', f're-detected {t[2]}',
              f'deferred {t[3]} ({t[4]} provisional)', f'track p50/p99 {t[6]}/{t[7]} ms',
              f'detect p50/p99 {t[8]}/{t[9]} ms', f'frame overruns {t[10]}']
f = find(r'frames with boxes (\d+), frame median ([\d.]+) ms p99 ([\d.]+) ms; refreshed (\d+) \((\d+) won\), '
         r'forced (\d+), longest wait (\d+)')
if f:
    parts += [f'frame p50/p99 {f[1]}/{f[2]} ms', f'refreshed {f[3]} ({f[4]} won)', f'forced {f[5]}',
              f'longest wait {f[6]}']
else:
    box = find(r'per box median ([\d.]+) ms, p99 ([\d.]+) ms')
    if box:
        parts.append(f'box p50/p99 {box[0]}/{box[1]} ms')
    over = find(r'overruns (\d+) frames')
    if over:
        parts.append(f'frame overruns {over[0]}')

import os
if a.sequences and os.path.exists(a.sequences):
    seqs = json.load(open(a.sequences))
    scenes = seqs['scenes'] if isinstance(seqs, dict) else seqs
    diam = {o['obj_id']: o['diameter'] for o in rep['objects']}
    right = collections.defaultdict(set)
    for e in rep['estimates']:
        if e['matched'] and e['error_mm'] is not None and e['error_mm'] < 0.1 * diam[e['obj_id']]:
            right[(e['scene_id'], e['obj_id'])].add(e['im_id'])
    lags, never = [], 0
    for sc in scenes:
        for ev in sc['events']:
            if ev['kind'] not in ('move', 'put_down'):
                continue
            frames = sorted(f for f in right[(sc['scene_id'], ev['obj_id'])] if f >= ev['end_frame'])
            if frames:
                lags.append(frames[0] - ev['end_frame'])
            else:
                never += 1
    if lags or never:
        parts.append('right again after events (frames): ' + ','.join(map(str, lags)) +
                     (f'; never {never}' if never else ''))
print(' | '.join(parts))
