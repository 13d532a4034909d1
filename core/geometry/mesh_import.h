// SPDX-License-Identifier: MIT
#pragma once

// Meshes as users have them, for training (`ihf train`, `ihf render`): PLY
// through our own reader (ply_loader.h), and STL (ASCII and binary), OBJ
// and glTF 2.0 (.gltf, .glb) through Debian's assimp when the build found
// it (IHF_WITH_ASSIMP). The format is chosen by the file's extension.
// Coordinates are taken as millimetres, as in the PLY path; glTF's metres
// are not converted, so export such a model in millimetres.
//
// What assimp gives is made into the mesh the PLY path gives: polygons are
// triangulated, node transforms applied, vertices at the same position
// joined (STL repeats each corner per triangle; normals are not kept, as
// they differ per triangle there), points, lines and degenerate triangles
// dropped. A file with no triangle, with a non-finite coordinate or with
// more than the limits allow is refused, its path named in the error.
//
// The device's loop (`ihf run`) reads forests, never mesh files: this library is
// linked by the CLI for training and rendering only, so a device build
// without assimp keeps the PLY reader alone.

#include <cstdint>
#include <filesystem>

#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf {

struct MeshImportLimits {
	// Checked before assimp reads a byte: the file, and every file it
	// opens beside it (glTF buffers, OBJ materials), each and in total.
	uint64_t maxFileBytes = 512ull << 20;
	// Checked on what assimp returns, before our copy is made.
	uint64_t maxVertices = 16'000'000;
	uint64_t maxTriangles = 16'000'000;
	// Checked before assimp reads the file: glTF nodes, OBJ objects and
	// groups ('o', 'g' lines). Assimp makes a node of over 1 KB for each,
	// so a 10 MB file of empty ones would cost it gigabytes.
	uint64_t maxNodes = 100'000;
};

// True when this build reads STL, OBJ and glTF (assimp found).
bool meshImportHasAssimp();

// The formats loadMesh() reads, for messages and --help: "PLY, STL, OBJ,
// glTF (.gltf, .glb)", or "PLY" in a build without assimp.
const char *meshImportFormats();

// Loads a mesh by its extension (case-insensitive): .ply with loadPly(),
// .stl, .obj, .gltf and .glb with assimp. Anything else, or those four in
// a build without assimp, is an error naming the file.
Expected<Mesh> loadMesh(const std::filesystem::path &path, const MeshImportLimits &limits = {});

} // namespace ihf
