#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The paper's comparison on our synthetic benchmark: synthesise
# the scenes, train each object's forest with variable and with fixed
# parts, estimate with the three IHF variants and score them with ihf eval.
#
#   benchmarks/accuracy/run.sh OUT [OBJECTS] [IMAGES]
#
# OBJECTS defaults to 1,5,9,20 (ape, can, duck from LM-O; 20 = the Stanford
# bunny of config/models), IMAGES to 50 per object. Forests are reused when
# present in OUT/forests, so a run can be resumed. Needs build/bin/ihf.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
ihf="$root/build/bin/ihf"
out=${1:?usage: run.sh OUT [OBJECTS] [IMAGES]}
objects=${2:-1,5,9,20}
images=${3:-50}
lmo="$root/../shared/data/lmo"
mkdir -p "$out/models" "$out/forests" "$out/results"

# One models folder: the LM-O meshes and the bunny.
for f in "$lmo"/models/*.ply "$root"/config/models/*.ply; do ln -sf "$f" "$out/models/"; done
python3 - "$lmo/models/models_info.json" "$root/config/models/models_info.json" "$out/models/models_info.json" <<'PY'
import json, sys
info = json.load(open(sys.argv[1])); info.update(json.load(open(sys.argv[2])))
json.dump(info, open(sys.argv[3], 'w'), indent=1)
PY

if [ ! -d "$out/syn" ]; then
	"$ihf" synth --models "$out/models" --objects "$objects" --images "$images" --seed 11 \
		--distance 600:1100 --out "$out/syn" --quiet
fi

forests_var=() forests_fix=()
for id in ${objects//,/ }; do
	model=$(printf '%s/models/obj_%06d.ply' "$out" "$id")
	for kind in variable fixed; do
		f="$out/forests/obj${id}_$kind.ihf"
		if [ ! -f "$f" ]; then
			sed "s/^kind = .*/kind = \"$kind\"/" "$root/config/train.toml" > "$out/forests/train_$kind.toml"
			/usr/bin/time -f "train obj $id $kind: %e s wall, %M KB peak" \
				"$ihf" train --model "$model" --out "$f" --config "$out/forests/train_$kind.toml" 2>&1 |
				grep -v '%' | tee -a "$out/train.log"
		fi
	done
	forests_var+=(--forest "$id=$out/forests/obj${id}_variable.ihf")
	forests_fix+=(--forest "$id=$out/forests/obj${id}_fixed.ihf")
done

run() { # name, forests..., options...
	local name=$1; shift
	"$ihf" estimate --dataset "$out/syn" --boxes "$out/syn/boxes.json" --config "$root/config/estimate.toml" \
		--out "$out/results/$name.csv" --quiet "$@" 2>&1 | tail -1 | tee -a "$out/estimate.log"
	"$ihf" eval --dataset "$out/syn" --results "$out/results/$name.csv" --json "$out/results/$name.json" \
		> "$out/results/$name.txt"
	echo "== $name"; cat "$out/results/$name.txt"
}
run fixed_k0 "${forests_fix[@]}" --iterations 0 --paper
run fixed_k5 "${forests_fix[@]}" --iterations 5 --paper
run variable_k5 "${forests_var[@]}" --iterations 5 --paper
run variable_k5_icp "${forests_var[@]}" --iterations 5
run fixed_k5_icp "${forests_fix[@]}" --iterations 5 # the default: view search + ICP
