#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Tracking against a cold start every frame (issue "Streams at 30 fps"):
# 30 Hz synthetic sequences with 3 and with 8 objects on the table, each
# estimated four ways (cold and tracked, unbudgeted and inside 33 ms
# frames) and scored with ihf eval; then the real LM-O frame as a still
# stream of 30 frames with its eight boxes in 33 ms frames.
#
#   benchmarks/tracking/run.sh OUT
#
# Data sets (made once, reused when present in OUT):
#   seq3: ihf synth --sequence --objects 1,5,6,8,9,10,11,12 --sequences 2 --frames 300
#         --per-frame 3:3 --seed 3   (two sequences, three objects a frame)
#   seq8: the same with --per-frame 8:8 --seed 8   (two sequences, eight objects a frame)
#   forests: ihf train --config config/train.toml for the eight LM-O objects
# Needs build/bin/ihf. Time only on an otherwise idle machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
ihf="$root/build/bin/ihf"
out=${1:?usage: run.sh OUT}
objects=1,5,6,8,9,10,11,12
lmo="$root/../shared/data/lmo"
mkdir -p "$out/forests" "$out/results"

forests=()
for id in ${objects//,/ }; do
	f="$out/forests/obj$id.ihf"
	[ -f "$f" ] || "$ihf" train --model "$(printf '%s/models/obj_%06d.ply' "$lmo" "$id")" --out "$f" \
		--config "$root/config/train.toml"
	forests+=(--forest "$id=$f")
done

for n in 3 8; do
	[ -d "$out/seq$n" ] || "$ihf" synth --sequence --models "$lmo/models" --objects "$objects" --sequences 2 \
		--frames 300 --per-frame "$n:$n" --seed "$n" --out "$out/seq$n" --quiet
done

# name, dataset, options...: estimate, evaluate, one line of results.
run() {
	local name=$1 data=$2
	shift 2
	"$ihf" estimate --dataset "$data" --boxes "$data/boxes.json" "${forests[@]}" \
		--config "$root/config/estimate.toml" --out "$out/results/$name.csv" --quiet "$@" \
		2> "$out/results/$name.log"
	"$ihf" eval --dataset "$data" --results "$out/results/$name.csv" --json "$out/results/$name.json" \
		> "$out/results/$name.txt"
	python3 "$root/benchmarks/tracking/report.py" "$name" "$out/results/$name.json" "$out/results/$name.log" \
		--sequences "$data/sequences.json"
}

for n in 3 8; do
	d="$out/seq$n"
	run "seq${n}_cold_unbudgeted" "$d" --budget-ms 0
	run "seq${n}_track_unbudgeted" "$d" --budget-ms 0 --sequence
	run "seq${n}_cold_33ms" "$d" --budget-ms 33
	run "seq${n}_track_33ms" "$d" --budget-ms 33 --sequence
done

# The real LM-O frame as a still stream of 30 frames, eight boxes each.
still="$out/lmo_still"
if [ ! -d "$still" ]; then
	python3 "$root/benchmarks/tracking/still_stream.py" --dataset "$lmo" --scene 2 --image 3 --frames 30 --out "$still"
	python3 "$root/benchmarks/accuracy/gt_boxes.py" --dataset "$still" --out "$still/boxes.json" >/dev/null
fi
run lmo_still_track_33ms "$still" --budget-ms 33 --sequence
python3 "$root/benchmarks/tracking/frame_report.py" "$out/results/lmo_still_track_33ms.json" --from 3
run lmo_still_cold_33ms "$still" --budget-ms 33
python3 "$root/benchmarks/tracking/frame_report.py" "$out/results/lmo_still_cold_33ms.json" --from 3
