# SPDX-License-Identifier: MIT
# Cross build for 32-bit ARM hard-float boards with Debian 12's
# g++-arm-linux-gnueabihf and :armhf multiarch -dev packages; tests run under
# qemu-arm-static. See toolchain/cross-test.sh.
set(IHF_CROSS_TRIPLE arm-linux-gnueabihf)
set(IHF_CROSS_PROCESSOR armv7l)
set(IHF_CROSS_QEMU qemu-arm-static)
set(IHF_CROSS_DEB_ARCH armhf)
include(${CMAKE_CURRENT_LIST_DIR}/cross-debian.cmake)
