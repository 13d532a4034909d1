# SPDX-License-Identifier: MIT
# Shared part of the Debian 12 cross toolchain files. The including file sets
# IHF_CROSS_TRIPLE (GNU triple = Debian multiarch directory) and
# IHF_CROSS_PROCESSOR, IHF_CROSS_QEMU before including this file.
#
# Compiled libraries (libpng, zlib, tomlplusplus, qhull, gtest, libusb) come either
# from multiarch -dev packages installed with dpkg (libpng-dev:arm64 ...) in
# /usr/lib/<triple>, or, with -DIHF_CROSS_SYSROOT=DIR, from those packages
# unpacked into DIR (toolchain/cross-test.sh does that: it keeps working when
# the mirror's arm64 and amd64 versions of a Multi-Arch: same package differ,
# which dpkg refuses to co-install). Header-only libraries (Eigen,
# nlohmann-json, CLI11, nanoflann) are the host's, via /usr/share/*/cmake.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${IHF_CROSS_PROCESSOR})
set(CMAKE_C_COMPILER ${IHF_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${IHF_CROSS_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${IHF_CROSS_TRIPLE})

# Search only /usr (multiarch lib dir first) and the cross sysroot, never
# the build host's /usr/lib/x86_64-linux-gnu; programs come from the host.
set(IHF_CROSS_SYSROOT "" CACHE PATH "Unpacked target -dev packages (empty: multiarch /usr)")
set(CMAKE_FIND_ROOT_PATH ${IHF_CROSS_SYSROOT} /usr/${IHF_CROSS_TRIPLE})
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES IHF_CROSS_SYSROOT)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(CMAKE_IGNORE_PATH /usr/lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu/cmake)

# pkg-config (cairo, if switched on) must see the target's .pc files only.
set(ENV{PKG_CONFIG_LIBDIR}
    "${IHF_CROSS_SYSROOT}/usr/lib/${IHF_CROSS_TRIPLE}/pkgconfig:/usr/lib/${IHF_CROSS_TRIPLE}/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")
# The unpacked .pc files say prefix=/usr: prefix their paths with the sysroot.
if(IHF_CROSS_SYSROOT)
  set(ENV{PKG_CONFIG_SYSROOT_DIR} "${IHF_CROSS_SYSROOT}")
endif()

# binfmt_misc is not mounted on the build machine: run target programs
# (gtest discovery, ctest, tests that call the ihf CLI) through qemu-user.
# -L finds the target's dynamic loader and libc in the cross sysroot.
set(CMAKE_CROSSCOMPILING_EMULATOR ${IHF_CROSS_QEMU};-L;/usr/${IHF_CROSS_TRIPLE})
if(IHF_CROSS_SYSROOT)
  # libpng needs libz (in /lib/<triple>): let the linker and the loader
  # find the unpacked libraries.
  set(_ihf_libdirs ${IHF_CROSS_SYSROOT}/usr/lib/${IHF_CROSS_TRIPLE}
      ${IHF_CROSS_SYSROOT}/lib/${IHF_CROSS_TRIPLE})
  list(JOIN _ihf_libdirs ":" _ihf_libpath)
  set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_ihf_libpath}")
  set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_ihf_libpath}")
  list(APPEND CMAKE_CROSSCOMPILING_EMULATOR -E LD_LIBRARY_PATH=${_ihf_libpath})
endif()

# What Debian calls this architecture (for CPack's .deb).
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${IHF_CROSS_DEB_ARCH})
