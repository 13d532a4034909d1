#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the libFuzzer harnesses (clang, ASan + UBSan) in their own build
# folder and runs each for SECONDS (default 60) from its seed corpus, files
# of the tree. New inputs collect in BUILD/corpus/NAME, so later runs go on
# from there; a crash, leak, timeout, out-of-memory or sanitizer report
# leaves its input in BUILD/artifacts/NAME/ and fails the script. Prints
# per harness the executions and coverage (libFuzzer's cov: and ft:).
#
#   tests/fuzz/run.sh [SECONDS] [NAME...]     (NAME e.g. fuzz_ply; default all)
#
# Environment: IHF_FUZZ_BUILD (default build-fuzz), IHF_FUZZ_JOBS (build
# jobs, default the core count), IHF_FUZZ_FLAGS (more libFuzzer flags).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
seconds="${1:-60}"
shift || true
build="${IHF_FUZZ_BUILD:-$root/build-fuzz}"

mapfile -t pkgs < <(grep -v '^\s*#' "$root/toolchain/debian12-fuzz-packages.txt" | sed '/^\s*$/d')
missing=()
for p in "${pkgs[@]}"; do
	dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
	echo "fuzz: installing ${missing[*]}" >&2
	sudo=""
	[ "$(id -u)" -eq 0 ] || sudo="sudo"
	$sudo apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

launcher=()
if command -v ccache >/dev/null; then
	launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
t0=$SECONDS
CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DIHF_FUZZ=ON \
	-DIHF_BUILD_TESTS=OFF -DIHF_BUILD_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
cmake --build "$build" -j "${IHF_FUZZ_JOBS:-$(nproc)}" --target ihf_fuzzers
echo "fuzz: build $((SECONDS - t0)) s" >&2

# Seeds of each harness: files and folders of the tree. tests/data/fuzz
# holds inputs that once crashed or exhausted memory; the harness must pass
# them (-malloc_limit_mb holds libpng's claims too).
declare -A seeds=(
	[fuzz_forest_file]="tests/data/forest_amd64.ihf"
	[fuzz_recording]="tests/fuzz/corpus/recording"
	[fuzz_ply]="tests/fuzz/corpus/ply tests/data/fuzz/ply_end_header_without_newline.ply"
	[fuzz_mesh_import]="tests/fuzz/corpus/mesh tests/data/fuzz/stl_ascii_broken_midway.stl"
	[fuzz_bop_json]="tests/fuzz/corpus/bop_json config/models/models_info.json"
	[fuzz_depth_png]="tests/fuzz/corpus/depth_png tests/data/golden_frame.png
		tests/data/fuzz/png_text_chunk_claims_2gb.png tests/data/fuzz/png_header_claims_32768x32768.png"
	[fuzz_results_csv]="tests/fuzz/corpus/results_csv"
	[fuzz_box_feed]="tests/fuzz/corpus/box_feed"
	[fuzz_toml_config]="config/train.toml config/estimate.toml config/device.toml config/demo-train.toml"
)
names=("$@")
if ((${#names[@]} == 0)); then
	names=(fuzz_forest_file fuzz_recording fuzz_ply fuzz_mesh_import fuzz_bop_json fuzz_depth_png fuzz_results_csv
		fuzz_box_feed fuzz_toml_config)
fi

status=0
summary=()
for name in "${names[@]}"; do
	[ -n "${seeds[$name]+x}" ] || { echo "fuzz: no harness $name" >&2; exit 2; }
	corpus="$build/corpus/$name"
	artifacts="$build/artifacts/$name"
	mkdir -p "$corpus" "$artifacts"
	# A seed folder of its own per harness: libFuzzer reads folders, not
	# single files, and writes new inputs into the first folder only.
	seedDir="$build/seeds/$name"
	rm -rf "$seedDir"
	mkdir -p "$seedDir"
	for s in ${seeds[$name]}; do
		if [ -d "$root/$s" ]; then
			find "$root/$s" -maxdepth 1 -type f -exec cp {} "$seedDir/" \;
		else
			cp "$root/$s" "$seedDir/"
		fi
	done
	log="$build/$name.log"
	t1=$SECONDS
	rc=0
	# shellcheck disable=SC2086 # IHF_FUZZ_FLAGS holds several flags
	"$build/bin/$name" -max_total_time="$seconds" -rss_limit_mb=512 -malloc_limit_mb=256 -timeout=10 \
		-print_final_stats=1 -artifact_prefix="$artifacts/" ${IHF_FUZZ_FLAGS:-} "$corpus" "$seedDir" \
		>"$log" 2>&1 &
	pid=$!
	wait "$pid" || rc=$?
	# The harness's input file (tests/fuzz/fuzz_input.h), named by its pid.
	rm -f "/dev/shm/ihf_fuzz_${pid}_"* "${TMPDIR:-/tmp}/ihf_fuzz_${pid}_"*
	# The last status line: "#N  DONE  cov: C ft: F corp: ..."
	last="$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)"
	execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")"
	cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")"
	ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")"
	line="$name: exit $rc, ${execs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, $((SECONDS - t1)) s"
	summary+=("$line")
	echo "fuzz: $line" >&2
	if [ "$rc" -ne 0 ]; then
		status=1
		grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -n 20 >&2 || true
	fi
done
printf 'fuzz: %s\n' "${summary[@]}" >&2
echo "fuzz: total $((SECONDS - t0)) s" >&2
exit "$status"
