# SPDX-License-Identifier: MIT
# Cross build for 64-bit ARM (Raspberry Pi 4/5, Jetson) with Debian 12's
# g++-aarch64-linux-gnu and :arm64 multiarch -dev packages; tests run under
# qemu-aarch64-static. See toolchain/cross-test.sh.
set(IHF_CROSS_TRIPLE aarch64-linux-gnu)
set(IHF_CROSS_PROCESSOR aarch64)
set(IHF_CROSS_QEMU qemu-aarch64-static)
set(IHF_CROSS_DEB_ARCH arm64)
include(${CMAKE_CURRENT_LIST_DIR}/cross-debian.cmake)
