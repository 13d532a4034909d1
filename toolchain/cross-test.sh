#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cross-builds ihf for ARCH (aarch64 | armhf) and runs the unit tests under
# qemu-user. Usage: toolchain/cross-test.sh ARCH [extra ctest args]
#
# Installs what is missing: the cross compiler and qemu-user-static (host
# packages), then the target's compiled -dev packages (libpng, zlib,
# tomlplusplus, qhull, gtest/gmock, libusb, libsystemd), downloaded with apt for the target
# architecture and unpacked into build-ARCH/sysroot (not dpkg-installed:
# Debian mirrors are often mid-sync, and Multi-Arch: same packages must then
# have identical amd64 and arm versions, which dpkg would refuse).
# Optional dependencies without an unpacked target package are switched off:
# OpenNI2, cairo (PR plots), Google Benchmark, libcamera (found by
# pkg-config only if its .pc is in the sysroot).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
arch="${1:-}"
shift || true
case "$arch" in
aarch64) triple=aarch64-linux-gnu; debarch=arm64; qemu=qemu-aarch64-static ;;
armhf) triple=arm-linux-gnueabihf; debarch=armhf; qemu=qemu-arm-static ;;
*)
	echo "usage: $0 aarch64|armhf [ctest args]" >&2
	exit 2
	;;
esac
build="$root/build-$arch"
sysroot="$build/sysroot"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

# Host side: cross compiler and emulator.
host_pkgs=("g++-$triple" qemu-user-static cmake ninja-build)
missing=()
# Captured first: with pipefail, grep -q exiting early can make the
# writer's SIGPIPE count as a failure.
for p in "${host_pkgs[@]}"; do
	st="$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)"
	[ "$st" = "install ok installed" ] || missing+=("$p")
done
foreign="$(dpkg --print-foreign-architectures)"
if ! grep -qx "$debarch" <<<"$foreign"; then
	echo "cross-test: adding dpkg architecture $debarch" >&2
	$sudo dpkg --add-architecture "$debarch"
	need_update=1
fi
# The architecture can be there without its package lists (an earlier update
# that failed half-way): update then too.
if ! apt-cache show "zlib1g:$debarch" >/dev/null 2>&1; then
	need_update=1
fi
if ((${#missing[@]})) || [ -n "${need_update:-}" ]; then
	$sudo apt-get update -qq || echo "cross-test: apt-get update reported errors; going on" >&2
fi
if ((${#missing[@]})); then
	echo "cross-test: installing ${missing[*]}" >&2
	DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Target side: compiled libraries, unpacked. Run-time libraries come along
# for the tests; libc and libstdc++ are the cross toolchain's.
target_pkgs=(libpng-dev libpng16-16 zlib1g-dev zlib1g libtomlplusplus-dev libtomlplusplus3
	libmeshoptimizer-dev libmeshoptimizer2d
	libqhull-dev libqhull8.0 libqhull-r8.0 libqhullcpp8.0 libgtest-dev libgmock-dev
	libusb-1.0-0-dev libusb-1.0-0 libudev1
	libsystemd-dev libsystemd0 libcap2 libgcrypt20 libgpg-error0 liblz4-1 liblzma5 libzstd1)
stamp="$sysroot/.packages"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "${target_pkgs[*]}" ]; then
	echo "cross-test: unpacking ${target_pkgs[*]} ($debarch) into $sysroot" >&2
	rm -rf "$sysroot"
	mkdir -p "$sysroot/debs"
	(cd "$sysroot/debs" && apt-get download -qq "${target_pkgs[@]/%/:$debarch}")
	for d in "$sysroot"/debs/*.deb; do dpkg -x "$d" "$sysroot"; done
	# Absolute symlinks (libz.so -> /lib/<triple>/libz.so.1...) must point
	# inside the sysroot.
	find "$sysroot" -type l -lname '/*' | while read -r l; do
		ln -sfn "$sysroot$(readlink "$l")" "$l"
	done
	echo "${target_pkgs[*]}" >"$stamp"
fi

cmake -S "$root" -B "$build" -G Ninja \
	-DCMAKE_TOOLCHAIN_FILE="$here/$triple.cmake" \
	-DIHF_CROSS_SYSROOT="$sysroot" \
	-DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
	-DIHF_SHARED_DIR="${IHF_SHARED_DIR:-$(dirname "$root")/shared}" \
	-DIHF_WITH_OPENNI2=OFF -DIHF_WITH_CAIRO=OFF -DIHF_BUILD_BENCHMARKS=OFF >/dev/null

# Only what the unit tests need, plus the CLI and the drivers.
# The test executables whose ihf_add_test() carries the unit label.
mapfile -t unit_targets < <(awk '/ihf_add_test\(/ { blk = ""; inb = 1 }
	inb { blk = blk " " $0 }
	inb && /\)/ {
		if (blk ~ /LABELS[^)]*unit/ && match(blk, /NAME [A-Za-z0-9_]+/))
			print substr(blk, RSTART + 5, RLENGTH - 5)
		inb = 0
	}' "$root"/tests/*/CMakeLists.txt)
# Keep those this configuration defines (some depend on optional libraries).
mapfile -t defined < <(ninja -C "$build" -t targets all | sed -n 's/^\([A-Za-z0-9_]*\): phony$/\1/p')
unit_targets=($(printf '%s\n' "${unit_targets[@]}" | grep -Fxf <(printf '%s\n' "${defined[@]}")))
targets=(ihf ihf_drivers "${unit_targets[@]}")
# IHF_CROSS_TARGETS="a b": only those (then run ctest with a matching -R).
[ -z "${IHF_CROSS_TARGETS:-}" ] || read -r -a targets <<<"$IHF_CROSS_TARGETS"
echo "cross-test: building ${targets[*]}" >&2
cmake --build "$build" -j "${IHF_JOBS:-2}" --target "${targets[@]}"

# Skipped under emulation: timing-sensitive tests (label "timing") and long
# statistical ones (label "long"), whose code test_golden_pose runs there.
cd "$build"
ctest -L unit -LE 'timing|long' --output-on-failure -j "${IHF_JOBS:-2}" --timeout 1200 "$@"
