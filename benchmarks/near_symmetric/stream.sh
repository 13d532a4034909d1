#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The nearly symmetric objects in a stream: 30 Hz sequences of the cup,
# camera and bottle on a table among the LM-O objects (clutter), estimated
# inside 33 ms frames with tracking (ihf estimate --sequence) and with a
# cold start every frame, and tracked without a budget (results/track_0ms),
# scored by ADD and by the visible surface
# (ihf eval --vsd) and split by whether the part shows at the true pose
# (part_visibility, split.py): where it shows, tracked poses should be
# right and not flagged ambiguous.
#
#   benchmarks/near_symmetric/stream.sh NEARSYM OUT
#
# NEARSYM is the output of benchmarks/near_symmetric/run.sh (its models,
# bodies and forests are used). Data set (made once, reused when present):
#   OUT/models: the LM-O models and the three procedural ones in one folder
#   OUT/seq: ihf synth --sequence --models OUT/models --objects 31,32,33
#            --sequences 3 --frames 300 --per-frame 3:3 --seed 47
# The runs are timed: run on an idle machine. Needs build/bin/ihf and
# build/bin/part_visibility.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
ihf="$root/build/bin/ihf"
ns=${1:?usage: stream.sh NEARSYM OUT}
out=${2:?usage: stream.sh NEARSYM OUT}
lmo="$root/../shared/data/lmo"
mkdir -p "$out/models" "$out/results"

if [ ! -f "$out/models/models_info.json" ]; then
	cp "$lmo"/models/*.ply "$ns"/models/*.ply "$out/models/"
	python3 - "$lmo/models/models_info.json" "$ns/models/models_info.json" "$out/models/models_info.json" <<'EOF'
import json, sys
info = json.load(open(sys.argv[1]))
info.update(json.load(open(sys.argv[2])))
json.dump(info, open(sys.argv[3], 'w'), indent=1)
EOF
fi
[ -d "$out/seq" ] || "$ihf" synth --sequence --models "$out/models" --objects 31,32,33 --sequences 3 \
	--frames 300 --per-frame 3:3 --seed 47 --out "$out/seq" --quiet
[ -f "$out/results/visibility.jsonl" ] ||
	"$root/build/bin/part_visibility" "$out/seq" "$ns/bodies" "$out/results/visibility.jsonl"

forests=()
for id in 31 32 33; do
	forests+=(--forest "$id=$ns/forests/obj$id.ihf")
done
for run in track:33 cold:33 track:0; do
	mode=${run%:*} budget=${run#*:}
	r="$out/results/${mode}_${budget}ms"
	opt=()
	[ "$mode" = cold ] || opt=(--sequence)
	"$ihf" estimate --dataset "$out/seq" --boxes "$out/seq/boxes.json" "${forests[@]}" \
		--config "$root/config/estimate.toml" --budget-ms "$budget" "${opt[@]}" --stats-json "$r.stats.json" \
		--out "$r.csv" --quiet 2> "$r.log"
	grep -E 'tracking|ambiguous' "$r.log" || true
	"$ihf" eval --dataset "$out/seq" --results "$r.csv" --vsd --json "$r.eval.json" | tee "$r.eval.txt"
	python3 "$root/benchmarks/near_symmetric/split.py" "$out/seq" "$r.csv" "$out/results/visibility.jsonl" \
		"$r.stats.json" "$r.eval.json" | tee "$r.split.txt"
done
