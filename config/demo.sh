#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on its embedded default. Until the on-device loop and its
# bundled recording land (issue 5), it synthesises a small Kinect-like scene
# set of the bundled Stanford bunny and shows where it went.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/build/demo/bunny"
rm -rf "$out"
mkdir -p "$(dirname "$out")"
"$root/build/bin/ihf" synth --models "$root/config/models" --objects 20 --images 3 --seed 1 --out "$out"
echo "demo: synthetic BOP dataset in $out (depth/*.png, scene_gt.json, boxes.json)"
