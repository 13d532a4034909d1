#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The nearly symmetric objects' benchmark: objects of the paper's kind, nearly symmetric and told
# apart by a small part (ids 31 cup, 32 camera, 33 bottle; procedural,
# `ihf synth --make-object`). Makes the meshes and their bodies without the
# part, the synthetic scenes (110 images an object, occlusion 10-60 %), the
# forests (config/train.toml; each stores the near-symmetries training
# found), then estimates unbudgeted at k = 5 and inside a 33 ms frame
# (config/estimate.toml), scores them (ihf eval, by ADD and by the visible
# surface, AR_VSD) and splits the boxes by whether the part shows
# (part_visibility, split.py); then the same for each object alone on 400
# images.
#
#   benchmarks/near_symmetric/run.sh OUT
#
# Data sets, meshes and forests that exist are kept, so a run can be resumed;
# the estimates are made again. The budgeted runs are timed: run them on an
# idle machine. Needs build/bin/ihf and build/bin/part_visibility.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
ihf="$root/build/bin/ihf"
out=${1:?usage: run.sh OUT}
mkdir -p "$out/models" "$out/bodies" "$out/forests" "$out/results"

names=(cup camera bottle)
for i in 0 1 2; do
	id=$((31 + i))
	[ -f "$out/models/obj_0000$id.ply" ] || "$ihf" synth --make-object "${names[$i]}" --id $id --models "$out/models"
	[ -f "$out/bodies/obj_0000$id.ply" ] ||
		"$ihf" synth --make-object "${names[$i]}" --id $id --without-part --models "$out/bodies"
done

[ -d "$out/syn" ] || "$ihf" synth --models "$out/models" --objects 31,32,33 --images 110 --seed 50 \
	--distance 600:1100 --occlusion 0.1:0.6 --out "$out/syn" --quiet

forests=()
for id in 31 32 33; do
	f="$out/forests/obj$id.ihf"
	[ -f "$f" ] || "$ihf" train --model "$out/models/obj_0000$id.ply" --out "$f" --config "$root/config/train.toml"
	"$ihf" forest info "$f" | grep -A4 '^near-symmetries'
	forests+=(--forest "$id=$f")
done

"$root/build/bin/part_visibility" "$out/syn" "$out/bodies" "$out/results/visibility.jsonl"

for budget in 0 33; do
	r="$out/results/b$budget"
	"$ihf" estimate --dataset "$out/syn" --boxes "$out/syn/boxes.json" "${forests[@]}" \
		--config "$root/config/estimate.toml" --iterations 5 --budget-ms $budget --threads 2 \
		--stats-json "$r.stats.json" --out "$r.csv" --quiet
	"$ihf" eval --dataset "$out/syn" --results "$r.csv" --vsd --json "$r.eval.json" | tee "$r.eval.txt"
	python3 "$root/benchmarks/near_symmetric/split.py" "$out/syn" "$r.csv" "$out/results/visibility.jsonl" \
		"$r.stats.json" "$r.eval.json" | tee "$r.split.txt"
done

# Each object alone on a larger set (400 images: cup400 seed 54, cam400 seed 52, bot400 seed 53;
# the same distances and occlusion): on 110 boxes an object's F1 moves by about 0.02 when a
# few poses change, and the camera's lens is seldom hidden where no depth could tell the turns
# apart (3 boxes in each set above), so the shares are counted on more boxes.
sets=(cup400:31:54 cam400:32:52 bot400:33:53)
for s in "${sets[@]}"; do
	IFS=: read -r name id seed <<<"$s"
	[ -d "$out/$name" ] || "$ihf" synth --models "$out/models" --objects "$id" --images 400 --seed "$seed" \
		--distance 600:1100 --occlusion 0.1:0.6 --out "$out/$name" --quiet
	"$root/build/bin/part_visibility" "$out/$name" "$out/bodies" "$out/results/${name}_visibility.jsonl"
	for budget in 0 33; do
		r="$out/results/${name}_b$budget"
		"$ihf" estimate --dataset "$out/$name" --boxes "$out/$name/boxes.json" --forest "$id=$out/forests/obj$id.ihf" \
			--config "$root/config/estimate.toml" --iterations 5 --budget-ms $budget --threads 2 \
			--stats-json "$r.stats.json" --out "$r.csv" --quiet
		"$ihf" eval --dataset "$out/$name" --results "$r.csv" --vsd --json "$r.eval.json" | tee "$r.eval.txt"
		python3 "$root/benchmarks/near_symmetric/split.py" "$out/$name" "$r.csv" \
			"$out/results/${name}_visibility.jsonl" "$r.stats.json" "$r.eval.json" | tee "$r.split.txt"
	done
done
