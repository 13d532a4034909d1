#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The peer comparison in one command: IHF variants and every peer
# built into ihf_peers, on the same dataset and boxes, scored by ihf eval.
#
#   benchmarks/peers/run.sh DATASET BOXES OUTDIR FOREST_ARGS...
#
# FOREST_ARGS:
#   --forest ID=F.ihf         variable-part forest of object ID (required, repeatable)
#   --forest-fixed ID=F.ihf   fixed-part forest (optional): adds the fixed variants
#   --train-seconds S         training time of the variable forests (reported as
#   --train-seconds-fixed S     model preparation; "n/a" when not given)
#   --peers a,b               peers to run (default: all that ihf_peers --list shows)
#   --config FILE             estimation config (default: config/estimate.toml)
#   --box-budget-ms B[,B2..]  budgets of the device-mode rows, per box (default 33,50):
#                               the frame budget is B times the most boxes a frame has
#
# Writes OUTDIR/NAME.{csv,eval.json,stats.json,eval.txt,log}, OUTDIR/pr_NAME.png
# and OUTDIR/table.md, and prints the table. Needs build/bin/ihf and
# build/bin/ihf_peers (-DIHF_BUILD_PEERS=ON). Every method runs on one thread
# (ihf estimate --threads 1, OMP_NUM_THREADS=1).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${IHF_BIN_DIR:-$root/build/bin}
ihf="$bin/ihf"
peersBin="$bin/ihf_peers"
usage() { echo "usage: run.sh DATASET BOXES OUTDIR --forest ID=F.ihf [--forest-fixed ID=F.ihf] [--train-seconds S] [--train-seconds-fixed S] [--peers a,b] [--config FILE] [--box-budget-ms B[,B2..]]" >&2; exit 2; }
[ $# -ge 3 ] || usage
dataset=$1 boxes=$2 out=$3; shift 3
forests=() fixed=() ids=() trainVar="" trainFix="" peers="" config="$root/config/estimate.toml" boxBudgets=33,50
while [ $# -gt 0 ]; do
	case $1 in
	--forest) forests+=(--forest "$2"); ids+=("${2%%=*}"); shift 2 ;;
	--forest-fixed) fixed+=(--forest "$2"); shift 2 ;;
	--train-seconds) trainVar=$2; shift 2 ;;
	--train-seconds-fixed) trainFix=$2; shift 2 ;;
	--peers) peers=$2; shift 2 ;;
	--config) config=$2; shift 2 ;;
	--box-budget-ms) boxBudgets=$2; shift 2 ;;
	*) usage ;;
	esac
done
[ ${#forests[@]} -gt 0 ] || usage
[ -x "$ihf" ] || { echo "run.sh: $ihf missing (build the ihf target)" >&2; exit 1; }
[ -x "$peersBin" ] || { echo "run.sh: $peersBin missing (configure with -DIHF_BUILD_PEERS=ON, build ihf_peers)" >&2; exit 1; }
[ -n "$peers" ] || peers=$("$peersBin" --list | paste -sd, -)
objects=$(IFS=,; echo "${ids[*]}")
mkdir -p "$out"
export OMP_NUM_THREADS=1

score() { # name
	"$ihf" eval --dataset "$dataset" --results "$out/$1.csv" --objects "$objects" --targets "$boxes" \
		--json "$out/$1.eval.json" --plot "$out/pr_$1.png" > "$out/$1.eval.txt" ||
	"$ihf" eval --dataset "$dataset" --results "$out/$1.csv" --objects "$objects" --targets "$boxes" \
		--json "$out/$1.eval.json" > "$out/$1.eval.txt"
}
ihfRun() { # name, prep seconds, forest args..., options... (IHF_BUDGET_MS: per-box budget, 0 = none)
	local name=$1 prep=$2; shift 2
	echo "run.sh: $name" >&2
	"$ihf" estimate --dataset "$dataset" --boxes "$boxes" --config "$config" --out "$out/$name.csv" \
		--stats-json "$out/$name.stats.json" --budget-ms "${IHF_BUDGET_MS:-0}" --threads 1 --quiet "$@" \
		> "$out/$name.log" 2>&1
	echo "${prep:-null}" > "$out/$name.prep"
	score "$name"
}
ihfRun ihf_variable_k0 "$trainVar" "${forests[@]}" --iterations 0 --paper
ihfRun ihf_variable_k5 "$trainVar" "${forests[@]}" --iterations 5 --paper
ihfRun ihf_variable_k5_icp "$trainVar" "${forests[@]}" --iterations 5
if [ ${#fixed[@]} -gt 0 ]; then
	ihfRun ihf_fixed_k0 "$trainFix" "${fixed[@]}" --iterations 0 --paper
	ihfRun ihf_fixed_k5 "$trainFix" "${fixed[@]}" --iterations 5 --paper
	ihfRun ihf_fixed_k5_icp "$trainFix" "${fixed[@]}" --iterations 5 # config/train.toml's kind
	# The device mode: the default config inside a budget of B ms per box
	# (the budget bounds of config/estimate.toml apply), still one thread.
	# ihf estimate's budget is per frame, shared by its boxes. 33 ms per box
	# is 100x below OpenCV PPF's ~3.3 s.
	perFrame=$(python3 - "$boxes" "$objects" <<'PY'
import collections, json, sys
ids = {int(i) for i in sys.argv[2].split(',')}
n = collections.Counter((b['scene_id'], b['image_id']) for b in json.load(open(sys.argv[1]))
                        if b['category_id'] in ids)
print(max(n.values(), default=1))
PY
)
	for boxBudget in ${boxBudgets//,/ }; do
		IHF_BUDGET_MS=$(python3 -c "print($boxBudget * $perFrame)") \
			ihfRun "ihf_fixed_budget${boxBudget}" "$trainFix" "${fixed[@]}"
	done
fi
for p in ${peers//,/ }; do
	echo "run.sh: $p" >&2
	"$peersBin" --peer "$p" --dataset "$dataset" --boxes "$boxes" --objects "$objects" --out "$out/$p.csv" \
		--stats-json "$out/$p.stats.json" --quiet > "$out/$p.log" 2>&1
	score "$p"
done

python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
names = [f[:-10] for f in sorted(os.listdir(out)) if f.endswith('.eval.json')]
names.sort(key=lambda n: (not n.startswith('ihf'), n))
rows = ['| method | mean F1 (z 0.05-0.15) | F1 @0.10 | ADD(-S)-0.1d recall | median ms/box | p99 ms/box | model prep s |',
        '|---|---|---|---|---|---|---|']
for n in names:
    ev = json.load(open(os.path.join(out, n + '.eval.json')))
    st = json.load(open(os.path.join(out, n + '.stats.json')))
    z = ev['z_values']; k = min(range(len(z)), key=lambda i: abs(z[i] - 0.10))
    m = ev['mean']
    if 'prep_s_total' in st:
        prep = '%.2f' % st['prep_s_total']
    else:
        p = open(os.path.join(out, n + '.prep')).read().strip()
        prep = 'n/a' if p == 'null' else '%.0f (training)' % float(p)
    rows.append('| %s | %.3f | %.3f | %.3f | %.1f | %.1f | %s |' % (
        n, m['mean_f1'], m['f1'][k], m['recall_0.1d'], st['box_ms']['p50'], st['box_ms']['p99'], prep))
text = '\n'.join(rows) + '\n'
open(os.path.join(out, 'table.md'), 'w').write(text)
print(text, end='')
PY
