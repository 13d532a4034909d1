# SPDX-License-Identifier: MIT
# Precompiled headers (IHF_PCH): CI builds the code four times (amd64, its
# sanitizer build, aarch64, armhf) on two cores, and Eigen alone costs ~2 s
# of parsing per source file. Two anchor targets precompile the common headers once per
# build; every other C++ target reuses their PCH (REUSE_FROM), so the
# flags of all of them must match. Targets with their own flags that change
# what the headers mean (EIGEN_RUNTIME_NO_MALLOC, -UNDEBUG, -fPIC) keep
# parsing the headers themselves. The sanitizer build's flags are
# project-wide, the anchors' too, so its targets share the PCH as well. GCC
# checks that a PCH fits the command line and otherwise falls back to the
# header text (-Winvalid-pch says so), so a mismatch costs time, never
# correctness.
set(_ihf_pch_headers
  <algorithm> <array> <chrono> <cmath> <cstdint> <cstdio> <cstring> <filesystem>
  <fstream> <map> <memory> <optional> <random> <span> <string> <vector>
  <Eigen/Core> <Eigen/Geometry>)

function(_ihf_collect_targets dir out)
  get_property(t DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(s ${subdirs})
    _ihf_collect_targets(${s} sub)
    list(APPEND t ${sub})
  endforeach()
  set(${out} ${t} PARENT_SCOPE)
endfunction()

# Call after every add_subdirectory().
function(ihf_enable_pch)
  file(WRITE ${CMAKE_BINARY_DIR}/pch_anchor.cpp "// PCH anchor\n")
  add_library(ihf_pch_core STATIC ${CMAKE_BINARY_DIR}/pch_anchor.cpp)
  target_link_libraries(ihf_pch_core PRIVATE Eigen3::Eigen)
  target_precompile_headers(ihf_pch_core PRIVATE ${_ihf_pch_headers})
  set(_test_anchor "")
  if(TARGET GTest::gtest)
    add_library(ihf_pch_test STATIC ${CMAKE_BINARY_DIR}/pch_anchor.cpp)
    target_link_libraries(ihf_pch_test PRIVATE Eigen3::Eigen GTest::gtest)
    target_precompile_headers(ihf_pch_test PRIVATE ${_ihf_pch_headers} <gtest/gtest.h>)
    set(_test_anchor ihf_pch_test)
  endif()

  _ihf_collect_targets(${PROJECT_SOURCE_DIR} targets)
  foreach(t ${targets})
    get_target_property(type ${t} TYPE)
    if(NOT type MATCHES "^(STATIC_LIBRARY|EXECUTABLE|OBJECT_LIBRARY)$"
       OR t MATCHES "^ihf_pch_")
      continue()
    endif()
    get_target_property(pic ${t} POSITION_INDEPENDENT_CODE)
    get_target_property(opts ${t} COMPILE_OPTIONS)
    get_target_property(defs ${t} COMPILE_DEFINITIONS)
    if(pic OR "${opts}" MATCHES "UNDEBUG" OR "${defs}" MATCHES "EIGEN_")
      continue()
    endif()
    # The headers must also be reachable as text (GCC's fallback).
    target_include_directories(${t} SYSTEM PRIVATE
      $<TARGET_PROPERTY:Eigen3::Eigen,INTERFACE_INCLUDE_DIRECTORIES>)
    get_target_property(libs ${t} LINK_LIBRARIES)
    if(_test_anchor AND "${libs}" MATCHES "GTest::")
      target_precompile_headers(${t} REUSE_FROM ${_test_anchor})
    else()
      target_precompile_headers(${t} REUSE_FROM ihf_pch_core)
    endif()
  endforeach()
endfunction()
