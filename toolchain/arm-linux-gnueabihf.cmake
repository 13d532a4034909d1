# SPDX-License-Identifier: MIT
# Cross build for 32-bit ARM hard-float boards with Debian 12's
# g++-arm-linux-gnueabihf and :armhf multiarch -dev packages; tests run under
# qemu-arm-static. See toolchain/cross-test.sh.
set(IHF_CROSS_TRIPLE arm-linux-gnueabihf)
set(IHF_CROSS_PROCESSOR armv7l)
set(IHF_CROSS_QEMU qemu-arm-static)
set(IHF_CROSS_DEB_ARCH armhf)
include(${CMAKE_CURRENT_LIST_DIR}/cross-debian.cmake)
# GCC notes on every function taking a std::span or an iterator by value
# that their passing changed in GCC 7.1 (an ABI note for mixing with code
# built before it; all of this is built by one compiler): thousands of log
# lines that hide the warnings that matter.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
