// SPDX-License-Identifier: MIT
#pragma once

// PLY reader for BOP model files: ASCII and binary little-endian, vertex
// x/y/z (+ optional nx/ny/nz, colours and other properties skipped), faces as
// lists of indices (polygons are fan-triangulated). Errors name the file and
// the element/property or line at fault.

#include <filesystem>

#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf {

Expected<Mesh> loadPly(const std::filesystem::path &path);

// Writes a binary little-endian PLY (vertices, normals if present, faces;
// ply_writer.cpp).
Status savePly(const std::filesystem::path &path, const Mesh &mesh);

} // namespace ihf
