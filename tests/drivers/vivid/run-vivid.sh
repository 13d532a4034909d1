#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Boots Debian's own kernel under QEMU (TCG) with the vivid V4L2 test driver
# and runs ihf's V4L2 capture checks inside it.
#
#   run-vivid.sh WORK_DIR CAPTURE_BINARY
#
# The kernel package (the one linux-image-amd64 depends on) is fetched once
# with `apt-get download` from Debian's apt into WORK_DIR/cache and unpacked
# there with `dpkg -x`; nothing is installed on this machine. An initramfs
# is built from busybox-static, the media modules (decompressed) and the
# static capture binary; /init loads the modules in dependency order, runs
# the capture and powers off. The console goes to WORK_DIR/console.log.
# Exit status: 0 when the VM ran (the checks' results are in the log) or
# when QEMU is missing (then WORK_DIR/qemu-missing says so and the tests
# skip), 1 on any set-up failure.
set -euo pipefail

work="$1"
capture="$2"
mkdir -p "$work/cache"
rm -f "$work/console.log" "$work/qemu-missing"
if ! command -v qemu-system-x86_64 >/dev/null; then
	echo "qemu-system-x86_64 is not installed" | tee "$work/qemu-missing" >&2
	exit 0
fi
command -v busybox >/dev/null || { echo "run-vivid: busybox (busybox-static) not installed" >&2; exit 1; }

# The kernel: Debian's current amd64 flavour, cached by package name.
pkg="$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')"
[ -n "$pkg" ] || { echo "run-vivid: apt knows no linux-image-amd64 (apt-get update?)" >&2; exit 1; }
tree="$work/cache/$pkg"
if [ ! -d "$tree" ]; then
	( cd "$work/cache" && ls "${pkg}"_*.deb >/dev/null 2>&1 || apt-get download -q "$pkg" ) >&2
	deb="$(ls "$work/cache/${pkg}"_*.deb | head -n 1)"
	rm -rf "$tree.tmp"
	dpkg -x "$deb" "$tree.tmp"
	# Only the kernel and the media modules are kept (400 MB -> about 20 MB).
	find "$tree.tmp/lib/modules" -mindepth 1 -maxdepth 1 -type d | while read -r v; do
		mkdir -p "$tree.tmp/keep"
		mv "$v/kernel/drivers/media" "$tree.tmp/keep/media"
		rm -rf "$v"
		mkdir -p "$v/kernel/drivers"
		mv "$tree.tmp/keep/media" "$v/kernel/drivers/media"
	done
	rm -rf "$tree.tmp/keep" "$tree.tmp/usr" "$tree.tmp/etc"
	mv "$tree.tmp" "$tree"
	rm -f "$deb" # the unpacked tree is the cache
fi
vmlinuz="$(ls "$tree"/boot/vmlinuz-* | head -n 1)"
media="$(ls -d "$tree"/lib/modules/*/kernel/drivers/media)"

# Dependency order (each module's "depends=" comes before it).
modules=(mc/mc v4l2-core/videodev rc/rc-core cec/core/cec v4l2-core/v4l2-dv-timings
	common/videobuf2/videobuf2-common common/videobuf2/videobuf2-v4l2
	common/videobuf2/videobuf2-memops common/videobuf2/videobuf2-vmalloc
	common/videobuf2/videobuf2-dma-contig common/v4l2-tpg/v4l2-tpg test-drivers/vivid/vivid)

root="$work/initramfs"
rm -rf "$root"
mkdir -p "$root"/{bin,dev,proc,sys,tmp,lib/modules}
cp "$(command -v busybox)" "$root/bin/busybox"
for a in sh mount insmod poweroff sleep echo cat ls; do ln -s busybox "$root/bin/$a"; done
names=()
for m in "${modules[@]}"; do
	name="$(basename "$m")"
	if [ -f "$media/$m.ko" ]; then
		cp "$media/$m.ko" "$root/lib/modules/$name.ko"
	elif [ -f "$media/$m.ko.xz" ]; then
		xz -dc "$media/$m.ko.xz" >"$root/lib/modules/$name.ko"
	elif [ -f "$media/$m.ko.zst" ]; then
		zstd -qdc "$media/$m.ko.zst" >"$root/lib/modules/$name.ko"
	else
		echo "run-vivid: $pkg has no module $m" >&2
		exit 1
	fi
	names+=("$name")
done
cp "$capture" "$root/bin/ihf_v4l2_capture"
cat >"$root/init" <<INIT
#!/bin/sh
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
for m in ${names[*]}; do
	insmod /lib/modules/\$m.ko || echo "IHF-V4L2 INSMOD-FAILED \$m"
done
echo "IHF-V4L2 BOOTED \$(cat /proc/version)"
/bin/ihf_v4l2_capture
echo "IHF-V4L2-EXIT \$?"
poweroff -f
INIT
chmod +x "$root/init"
( cd "$root" && find . | busybox cpio -o -H newc 2>/dev/null | gzip -1 ) >"$work/initramfs.gz"

# TCG (no KVM here); the console on the serial port is the log.
timeout 600 qemu-system-x86_64 -accel tcg -m 512M -smp 1 -nographic -no-reboot \
	-kernel "$vmlinuz" -initrd "$work/initramfs.gz" \
	-append "console=ttyS0 panic=-1 rdinit=/init loglevel=4" >"$work/console.log" 2>&1 </dev/null || true
grep -q "IHF-V4L2-RESULT" "$work/console.log" || { echo "run-vivid: the VM did not finish; see $work/console.log" >&2; exit 1; }
