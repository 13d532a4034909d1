#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Tracking against a cold start every frame (issue "Streams at 30 fps"):
# 30 Hz synthetic sequences with 3 and with 8 objects on the table,
# estimated with tracking (ihf estimate --sequence) and with a cold start
# every frame, unbudgeted and inside 33 ms frames, scored with ihf eval on
# every frame and, against the unbudgeted cold start (a full detection per
# box, so measured on every 5th frame), on those frames; then the real LM-O
# frame as a still stream of 30 frames with its eight boxes in 33 ms frames.
#
#   benchmarks/tracking/run.sh OUT
#
# Data sets (made once, reused when present in OUT):
#   seq3: ihf synth --sequence --models LMO/models --objects 1,5,6,8,9,10,11,12
#         --sequences 3 --frames 300 --per-frame 3:3 --seed 47
#   seq8: the same with --per-frame 8:8 (eight objects a frame)
#   seqN_every5: benchmarks/tracking/subset.py --dataset seqN --every 5
#   forests: ihf train --config config/train.toml for the eight LM-O objects
# Needs build/bin/ihf. Time only on an otherwise idle machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
ihf="$root/build/bin/ihf"
out=${1:?usage: run.sh OUT}
objects=1,5,6,8,9,10,11,12
lmo="$root/../shared/data/lmo"
here="$root/benchmarks/tracking"
mkdir -p "$out/forests" "$out/results"

forests=()
for id in ${objects//,/ }; do
	f="$out/forests/obj$id.ihf"
	[ -f "$f" ] || "$ihf" train --model "$(printf '%s/models/obj_%06d.ply' "$lmo" "$id")" --out "$f" \
		--config "$root/config/train.toml"
	forests+=(--forest "$id=$f")
done

for n in 3 8; do
	[ -d "$out/seq$n" ] || "$ihf" synth --sequence --models "$lmo/models" --objects "$objects" --sequences 3 \
		--frames 300 --per-frame "$n:$n" --seed 47 --out "$out/seq$n" --quiet
	[ -d "$out/seq${n}_every5" ] || python3 "$here/subset.py" --dataset "$out/seq$n" --every 5 --out "$out/seq${n}_every5"
done

# name, dataset: score results/NAME.csv, one line of results.
score() {
	"$ihf" eval --dataset "$2" --results "$out/results/$1.csv" --json "$out/results/$1.json" > "$out/results/$1.txt"
	python3 "$here/report.py" "$1" "$out/results/$1.json" "$out/results/${3:-$1}.log" --sequences "$2/sequences.json"
}
# name, dataset, options...: estimate, then score.
run() {
	local name=$1 data=$2
	shift 2
	"$ihf" estimate --dataset "$data" --boxes "$data/boxes.json" "${forests[@]}" \
		--config "$root/config/estimate.toml" --out "$out/results/$name.csv" --quiet "$@" \
		2> "$out/results/$name.log"
	score "$name" "$data"
}

for n in 3 8; do
	d="$out/seq$n"
	run "seq${n}_track_unbudgeted" "$d" --budget-ms 0 --sequence
	run "seq${n}_track_33ms" "$d" --budget-ms 33 --sequence
	run "seq${n}_cold_33ms" "$d" --budget-ms 33
	# [tracking] refresh measured against off.
	printf '[tracking]\nrefresh = false\n' > "$out/norefresh.toml"
	run "seq${n}_track_33ms_norefresh" "$d" --budget-ms 33 --sequence --run-config "$out/norefresh.toml"
	run "seq${n}_every5_cold_unbudgeted" "${d}_every5" --budget-ms 0
	for r in track_unbudgeted track_33ms cold_33ms track_33ms_norefresh; do
		python3 "$here/subset.py" --dataset "$d" --every 5 --csv "$out/results/seq${n}_$r.csv" \
			"$out/results/seq${n}_every5_$r.csv"
		score "seq${n}_every5_$r" "${d}_every5" "seq${n}_$r"
	done
	# The same past each sequence's first frames (subset.py's targets).
	for r in every5_cold_unbudgeted every5_track_33ms; do
		echo "seq${n}_${r}_after_start: $("$ihf" eval --dataset "${d}_every5" \
			--results "$out/results/seq${n}_$r.csv" --targets "${d}_every5/targets_after_start.json" |
			awk '/^mean/ {print "F1", $(NF-2), "recall", $(NF-1)}')"
	done
done

# The real LM-O frame as a still stream of 30 frames, eight boxes each.
still="$out/lmo_still"
if [ ! -d "$still" ]; then
	python3 "$here/still_stream.py" --dataset "$lmo" --scene 2 --image 3 --frames 30 --out "$still"
	python3 "$root/benchmarks/accuracy/gt_boxes.py" --dataset "$still" --out "$still/boxes.json" >/dev/null
fi
for mode in track cold; do
	opt=()
	[ "$mode" = cold ] || opt=(--sequence)
	"$ihf" estimate --dataset "$still" --boxes "$still/boxes.json" "${forests[@]}" \
		--config "$root/config/estimate.toml" --out "$out/results/lmo_still_$mode.csv" --quiet \
		--budget-ms 33 "${opt[@]}" 2> "$out/results/lmo_still_$mode.log"
	"$ihf" eval --dataset "$still" --results "$out/results/lmo_still_$mode.csv" \
		--json "$out/results/lmo_still_$mode.json" > /dev/null
	echo "lmo_still_${mode}_33ms: $(python3 "$here/frame_report.py" "$out/results/lmo_still_$mode.json" --from 3 | tr '\n' ' ')"
done
