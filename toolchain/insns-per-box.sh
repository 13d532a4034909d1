#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Instructions per box, amd64 vs aarch64, on the same small workload: the
# golden-pose test's first box (tests/data: the amd64-written ape forest and
# frame) with the initial registration only (IHF_GOLDEN_SMALL=1: no
# refinement, no ICP). Per box = run with one box - run with none (the
# latter loads the forest and frame and sets up the arena).
#   amd64:   valgrind --tool=callgrind (Ir)
#   aarch64: qemu-aarch64-static -d in_asm,exec,nochain into a FIFO, counted
#            by toolchain/qemu-insn-count.cpp (Debian 12's qemu-user-static
#            has no TCG plugins); slow: ~2-3 us of qemu time per executed
#            block, hence the small workload.
# Usage: toolchain/insns-per-box.sh NATIVE_BUILD AARCH64_BUILD
# (both with test_golden_pose built).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
native="${1:?native build dir}"
cross="${2:?aarch64 build dir}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
g++ -O2 -std=c++20 -o "$work/count" "$here/qemu-insn-count.cpp"
sys="$cross/sysroot"
lib="$sys/usr/lib/aarch64-linux-gnu:$sys/lib/aarch64-linux-gnu"

for boxes in 0 1; do
	# The test fails on purpose for a partial run; only the counts matter.
	IHF_GOLDEN_SMALL=1 IHF_GOLDEN_BOXES=$boxes valgrind --tool=callgrind \
		--callgrind-out-file="$work/cg.$boxes" "$native/bin/test_golden_pose" \
		>"$work/cg.$boxes.log" 2>&1 || true
	amd=$(sed -n 's/.*I *refs: *//p' "$work/cg.$boxes.log" | tr -d ,)
	mkfifo "$work/fifo.$boxes"
	"$work/count" <"$work/fifo.$boxes" >"$work/q.$boxes" &
	counter=$!
	IHF_GOLDEN_SMALL=1 IHF_GOLDEN_BOXES=$boxes qemu-aarch64-static -L /usr/aarch64-linux-gnu \
		-E LD_LIBRARY_PATH="$lib" -d in_asm,exec,nochain -D "$work/fifo.$boxes" \
		"$cross/bin/test_golden_pose" >"$work/q.$boxes.log" 2>&1 || true
	wait "$counter" || { echo "insns-per-box: blocks executed but never listed" >&2; exit 1; }
	arm=$(sed -n 's/^instructions //p' "$work/q.$boxes")
	echo "boxes $boxes: amd64 $amd aarch64 $arm"
	eval "amd$boxes=$amd arm$boxes=$arm"
done
echo "per box: amd64 $((amd1 - amd0)) aarch64 $((arm1 - arm0))"
