#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the libFuzzer harnesses in the debug preset's build (clang, ASan +
# UBSan, build-debug/: the sanitizer lane's build, so after
# toolchain/run-sanitizer-tests.sh nothing is left to compile) and runs each
# for SECONDS (default 60) from its seed corpus, files of the tree, as many
# at once as there are cores (each harness is one process). New inputs
# collect in build-debug/fuzz/corpus/NAME, so later runs go on from there; a
# crash, leak, timeout, out-of-memory or sanitizer report leaves its input
# in build-debug/fuzz/artifacts/NAME/ and fails the script. Prints per
# harness the executions and coverage (libFuzzer's cov: and ft:).
#
#   tests/fuzz/run.sh [SECONDS] [NAME...]     (NAME e.g. fuzz_ply; default all)
#
# Environment: IHF_FUZZ_PARALLEL (harnesses at once, default the core
# count), IHF_FUZZ_FLAGS (more libFuzzer flags).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
seconds="${1:-60}"
shift || true
build="$root/build-debug"
work="$build/fuzz"

t0=$SECONDS
"$root/toolchain/setup.sh" debug ihf_fuzzers
echo "fuzz: build $((SECONDS - t0)) s" >&2

# Seeds of each harness: files and folders of the tree. tests/data/fuzz
# holds inputs that once crashed or exhausted memory; the harness must pass
# them (-malloc_limit_mb holds libpng's claims too).
declare -A seeds=(
	[fuzz_forest_file]="tests/data/forest_amd64.ihf"
	[fuzz_recording]="tests/fuzz/corpus/recording"
	[fuzz_ply]="tests/fuzz/corpus/ply tests/data/fuzz/ply_end_header_without_newline.ply"
	[fuzz_mesh_import]="tests/fuzz/corpus/mesh tests/data/fuzz/stl_ascii_broken_midway.stl
		tests/data/fuzz/gltf_primitive_without_position.gltf"
	[fuzz_bop_json]="tests/fuzz/corpus/bop_json config/models/models_info.json"
	[fuzz_depth_png]="tests/fuzz/corpus/depth_png tests/data/golden_frame.png
		tests/data/fuzz/png_text_chunk_claims_2gb.png tests/data/fuzz/png_header_claims_32768x32768.png"
	[fuzz_results_csv]="tests/fuzz/corpus/results_csv"
	[fuzz_run_poses]="tests/fuzz/corpus/run_poses"
	[fuzz_box_feed]="tests/fuzz/corpus/box_feed"
	[fuzz_toml_config]="config/train.toml config/estimate.toml config/device.toml config/demo-train.toml"
)
names=("$@")
if ((${#names[@]} == 0)); then
	names=(fuzz_forest_file fuzz_recording fuzz_ply fuzz_mesh_import fuzz_bop_json fuzz_depth_png fuzz_results_csv
		fuzz_run_poses fuzz_box_feed fuzz_toml_config)
fi

# One harness: seeds, run, and its line of the summary in $work/NAME.result
# (the line, then its exit status).
fuzz_one() {
	local name="$1"
	local corpus="$work/corpus/$name" artifacts="$work/artifacts/$name" seedDir="$work/seeds/$name"
	mkdir -p "$corpus" "$artifacts"
	# A seed folder of its own per harness: libFuzzer reads folders, not
	# single files, and writes new inputs into the first folder only.
	rm -rf "$seedDir"
	mkdir -p "$seedDir"
	local s
	for s in ${seeds[$name]}; do
		if [ -d "$root/$s" ]; then
			find "$root/$s" -maxdepth 1 -type f -exec cp {} "$seedDir/" \;
		else
			cp "$root/$s" "$seedDir/"
		fi
	done
	local log="$work/$name.log" t1=$SECONDS rc=0
	# shellcheck disable=SC2086 # IHF_FUZZ_FLAGS holds several flags
	"$build/bin/$name" -max_total_time="$seconds" -rss_limit_mb=512 -malloc_limit_mb=256 -timeout=10 \
		-print_final_stats=1 -artifact_prefix="$artifacts/" ${IHF_FUZZ_FLAGS:-} "$corpus" "$seedDir" \
		>"$log" 2>&1 &
	local pid=$!
	wait "$pid" || rc=$?
	# The harness's input file (tests/fuzz/fuzz_input.h), named by its pid.
	rm -f "/dev/shm/ihf_fuzz_${pid}_"* "${TMPDIR:-/tmp}/ihf_fuzz_${pid}_"*
	# The last status line: "#N  DONE  cov: C ft: F corp: ..."
	local last execs cov ft
	last="$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)"
	execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")"
	cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")"
	ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")"
	local line="$name: exit $rc, ${execs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, $((SECONDS - t1)) s"
	echo "fuzz: $line" >&2
	if [ "$rc" -ne 0 ]; then
		grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -n 20 >&2 || true
	fi
	printf '%s\n%s\n' "$line" "$rc" >"$work/$name.result"
}

mkdir -p "$work"
parallel="${IHF_FUZZ_PARALLEL:-$(nproc)}"
for name in "${names[@]}"; do
	[ -n "${seeds[$name]+x}" ] || { echo "fuzz: no harness $name" >&2; exit 2; }
	rm -f "$work/$name.result"
done
t0=$SECONDS
for name in "${names[@]}"; do
	while (($(jobs -rp | wc -l) >= parallel)); do
		wait -n || true
	done
	fuzz_one "$name" &
done
wait || true
# Each harness printed its line as it ended; the summary names the failed.
status=0 failed=0
for name in "${names[@]}"; do
	if [ ! -f "$work/$name.result" ]; then
		echo "fuzz: failed: $name: no result" >&2
	elif [ "$(sed -n 2p "$work/$name.result")" != 0 ]; then
		sed -n 1p "$work/$name.result" | sed 's/^/fuzz: failed: /' >&2
	else
		continue
	fi
	status=1
	failed=$((failed + 1))
done
echo "fuzz: ${#names[@]} harnesses, $failed failed, runs $((SECONDS - t0)) s ($parallel at once)" >&2
exit "$status"
