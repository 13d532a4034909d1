#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The sanitizer lane: builds the debug preset (clang, AddressSanitizer +
# UBSan at -O2, build-debug/, no benchmarks; the same build holds the fuzz
# harnesses of tests/fuzz/run.sh) and runs every test under it (ctest
# --preset debug: LeakSanitizer on, any UBSan report fails its test). The
# V4L2 vivid VM check is not in this build: the program it boots is linked
# statically, which the sanitizers' runtimes do not allow.
# Prints the build and test wall times (BENCHMARKS.md, CI stage times).
#
#   toolchain/run-sanitizer-tests.sh [ctest args]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
t0=$SECONDS
"$here/setup.sh" debug
t1=$SECONDS
cd "$(dirname "$here")"
status=0
ctest --preset debug "$@" || status=$?
echo "sanitizers: build $((t1 - t0)) s, tests $((SECONDS - t1)) s, exit $status" >&2
exit "$status"
