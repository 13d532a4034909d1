#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The long soak of `ihf run` (BENCHMARKS.md, Soak): a 30 Hz sequence of the
# bunny played looped for FRAMES good frames, tracked, with corrupt frames
# (every 7th), truncated box lines (every 11th) and boxes of an object
# without a forest (every 5th line) mixed in (ihf_soak_inputs,
# tests/app/soak_inputs.h). While it runs, the process's RSS
# (/proc/PID/status) and the stats line's frame count and arena high-water
# mark are sampled every few seconds. The same run on the clean inputs (the
# bad ones left out), side by side with it for its first CLEAN_FRAMES good
# frames (default all), must give the same pose lines. Prints the samples at
# every tenth of the run and a summary; exits 1 if a count, the poses or the
# memory (RSS growth of 1 MB or more, or a higher arena high-water mark,
# after the first tenth of the run) is off.
#
#   benchmarks/soak/run.sh [FRAMES [OUT [CLEAN_FRAMES]]]   (default 100000, build/soak)
#
# Needs build/bin/ihf and build/bin/ihf_soak_inputs (the release build).
# The sequence, forest and inputs are made once and reused from OUT.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
frames=${1:-100000}
out=${2:-$root/build/soak}
ihf="$root/build/bin/ihf"
make_inputs="$root/build/bin/ihf_soak_inputs"
interval=${IHF_SOAK_SAMPLE_S:-5}
models="$root/config/models"
mkdir -p "$out"
cd "$out"

# A 150-frame sequence of the bunny (5 s at 30 Hz), a tiny forest and a
# lean, unbudgeted detector (poses that do not depend on the machine's
# speed), as in tests/app/commands/run_soak_test.cpp.
[ -d seq ] || "$ihf" synth --sequence --models "$models" --objects 20 --sequences 1 --frames 150 --seed 3 \
	--quiet --out seq
if [ ! -f bunny.ihf ]; then
	printf '[views]\nviewpoints = 20\ninplane_steps = 2\n[scales]\nfactors = [1.0]\nparts_per_image = 8\noccluded_views = 0.0\n[parts]\nkind = "variable"\nmax_control_points = 256\n' \
		>train.toml
	"$ihf" train --model "$models/obj_000020.ply" --config train.toml --out bunny.ihf >/dev/null
fi
cat >estimate.toml <<'EOF'
[refinement]
iterations = 0
depth_windows = 1
target_parts = 100
[icp]
candidates = 2
forest_bests = false
registration_candidates = false
[view_search]
inplane = 8
refine_top = 8
viewpoints = 60
depth_centres = 1
[half_turns]
candidates = 0
EOF
cat >device.toml <<EOF
[source]
uri = "recording:faulty.rec?loop=1"
[boxes]
input = "file:faulty.boxes.jsonl"
[output]
poses = "file:faulty.jsonl"
[objects]
20 = "bunny.ihf"
[estimate]
config = "estimate.toml"
[tracking]
enabled = true
[run]
stats_interval_s = $interval
EOF
if [ ! -f "inputs.$frames.env" ] || [ ! -f faulty.rec ] || [ ! -f clean.rec ]; then
	"$make_inputs" --recording seq/recordings/000001.rec --boxes seq/recordings/000001.boxes.jsonl \
		--out . --frames "$frames" >"inputs.$frames.env.tmp"
	mv "inputs.$frames.env.tmp" "inputs.$frames.env"
fi
# shellcheck disable=SC1090
. "./inputs.$frames.env"

# The number after KEY in the last stats line of a log.
stat_of() { { grep -o "[ ;(]$2 [0-9][0-9]*" "$1" || true; } | tail -n 1 | awk '{print $NF}'; }

clean_frames=${3:-$good_frames}

# Runs ihf run for FRAMES frames with the given arguments, sampling every
# $interval s into SAMPLES: elapsed s, frames so far, RSS kB, arena
# high-water bytes.
run_sampled() {
	local log=$1 samples=$2 count=$3
	shift 3
	: >"$samples"
	local t0=$SECONDS
	"$ihf" run --config device.toml --frames "$count" "$@" 2>"$log" &
	local pid=$!
	while kill -0 "$pid" 2>/dev/null; do
		sleep "$interval"
		local rss
		rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null) || break
		[ -n "$rss" ] || break
		local seen
		seen=$(stat_of "$log" frames)
		[ -n "$seen" ] || continue # no stats line yet
		echo "$((SECONDS - t0)) $seen $rss $(stat_of "$log" high-water)" >>"$samples"
	done
	wait "$pid"
	echo "$((SECONDS - t0))" >"$samples.wall"
}

# Both runs at once (each sampled on its own).
echo "soak: $good_frames frames ($passes passes of $records_per_pass), the faulty and the clean run" >&2
run_sampled faulty.log faulty.samples "$good_frames" &
faulty_pid=$!
run_sampled clean.log clean.samples "$clean_frames" --source "recording:clean.rec?loop=1" \
	--boxes file:clean.boxes.jsonl --out file:clean.jsonl &
clean_pid=$!
wait "$faulty_pid"
wait "$clean_pid"

# Pose lines without their timing fields; the faulty run's lines for unknown
# objects and malformed box lines apart.
poses_of() {
	grep -v '"error":"no forest for object' "$1" | grep -v '^{"error"' |
		sed -e 's/,"latency_ms":[^,}]*//' -e 's/,"estimate_ms":[^,}]*//'
}
pose_lines=$(poses_of clean.jsonl | wc -l)
same_poses=no
cmp -s <(poses_of faulty.jsonl | head -n "$pose_lines") <(poses_of clean.jsonl) && same_poses=yes

fail=0
check() { # name counted expected
	local ok=yes
	[ "$2" = "$3" ] || { ok=NO; fail=1; }
	printf '| %s | %s | %s | %s |\n' "$1" "$2" "$3" "$ok"
}
echo
echo "| count | counted | expected | ok |"
echo "|---|---:|---:|---|"
check "frames processed" "$(stat_of faulty.log processed)" "$good_frames"
check "corrupt frames" "$(stat_of faulty.log corrupt)" "$corrupt_frames"
check "truncated box lines (input-errors)" "$(stat_of faulty.log input-errors)" "$truncated_lines"
check "boxes of unknown objects" "$(stat_of faulty.log unknown-object)" "$unknown_boxes"
check "box lines read" "$(stat_of faulty.log 'box lines')" "$lines"
check "pose lines identical to the clean run's ($pose_lines, its $clean_frames frames)" "$same_poses" yes

echo
echo "| elapsed s | frames | RSS MB | arena high-water bytes |"
echo "|---:|---:|---:|---:|"
n=$(wc -l <faulty.samples)
for tenth in 0 1 2 3 4 5 6 7 8 9 10; do
	row=$(( tenth * (n - 1) / 10 + 1 ))
	sed -n "${row}p" faulty.samples
done | uniq | awk '{printf "| %d | %d | %.1f | %d |\n", $1, $2, $3 / 1024, $4}'

# Memory after the first tenth of the run (every kind of box seen by then).
tenth=$(( n / 10 + 1 ))
first_rss=$(head -n 1 faulty.samples | awk '{print $3}')
tenth_rss=$(sed -n "${tenth}p" faulty.samples | awk '{print $3}')
mid_rss=$(sed -n "$(( (n + 1) / 2 ))p" faulty.samples | awk '{print $3}')
last_rss=$(tail -n 1 faulty.samples | awk '{print $3}')
max_rss=$(tail -n "+$tenth" faulty.samples | awk 'm < $3 {m = $3} END {print m}')
tenth_hw=$(sed -n "${tenth}p" faulty.samples | awk '{print $4}')
last_hw=$(stat_of faulty.log high-water)
tracker_hw=$(stat_of faulty.log tracker)
growth=$(( max_rss - tenth_rss ))
echo
echo "soak: $good_frames frames in $(cat faulty.samples.wall) s (clean run: $clean_frames frames in" \
	"$(cat clean.samples.wall) s); RSS ${first_rss} kB at the first sample, ${tenth_rss} kB at a tenth," \
	"${mid_rss} kB in the middle, ${last_rss} kB at the end, peak growth after a tenth ${growth} kB;" \
	"arena high-water ${tenth_hw} bytes at a tenth, ${last_hw} at the end (tracker ${tracker_hw})"
[ "$growth" -lt 1024 ] || { echo "soak: RSS grew by ${growth} kB" >&2; fail=1; }
[ "$tenth_hw" = "$last_hw" ] || { echo "soak: the arena high-water mark grew" >&2; fail=1; }
exit "$fail"
