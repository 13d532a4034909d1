#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages ihf needs (only those missing), then
# configures and builds a preset (default release; debug: clang with ASan,
# UBSan and the fuzz harnesses in build-debug/, which also needs
# debian12-fuzz-packages.txt). Idempotent; safe to re-run.
#
#   toolchain/setup.sh [PRESET [TARGET...]]     (default: every target)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"

preset="${1:-release}"
shift || true
lists=("$here/debian12-packages.txt")
[ "$preset" != debug ] || lists+=("$here/debian12-fuzz-packages.txt")
mapfile -t pkgs < <(cat "${lists[@]}" | grep -v '^\s*#' | sed '/^\s*$/d')
missing=()
for p in "${pkgs[@]}"; do
	dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
	echo "setup: installing ${missing[*]}" >&2
	sudo=""
	[ "$(id -u)" -eq 0 ] || sudo="sudo"
	$sudo apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cd "$root"
cmake --preset "$preset" >/dev/null
targets=()
(($# == 0)) || targets=(--target "$@")
cmake --build --preset "$preset" "${targets[@]}"
