// SPDX-License-Identifier: MIT
// STL, OBJ and glTF meshes (ihf train, ihf render): loadMesh through
// assimp. The extension picks assimp's importer, so the input's first bytes
// pick it here: "glTF" a .glb, '{' a .gltf, "solid" an ASCII .stl, a
// letter or '#' an .obj, anything else a binary .stl. Seeds:
// tests/fuzz/corpus/mesh (written by tests/fuzz/corpus/make_mesh_seeds.py).

#include <cctype>
#include <cstring>

#include "core/geometry/mesh_import.h"
#include "tests/fuzz/fuzz_input.h"

namespace {

const char *nameFor(const uint8_t *data, size_t size)
{
	auto startsWith = [&](const char *s) { return size >= std::strlen(s) && std::memcmp(data, s, std::strlen(s)) == 0; };
	if (startsWith("glTF"))
		return "mesh.glb";
	if (startsWith("{"))
		return "mesh.gltf";
	if (startsWith("solid"))
		return "mesh.stl";
	if (size > 0 && (std::isalpha(data[0]) || data[0] == '#'))
		return "mesh.obj";
	return "mesh.stl";
}

} // namespace

// LeakSanitizer (ASan builds): ignore leaks whose allocation passes through
// Debian's assimp. assimp 5.2.5's ASCII STL importer drops the mesh and
// node it has made when a file breaks midway (~2.5 KB per refused file,
// once per `ihf train`; tests/data/fuzz/stl_ascii_broken_midway.stl). Our
// own leaks are still reported.
extern "C" const char *__lsan_default_suppressions()
{
	return "leak:libassimp.so\n";
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const auto path = ihf::fuzz::inputFile(data, size, nameFor(data, size));
	// Limits well under the run's -malloc_limit_mb, so that a file that
	// names another file in the input's folder (/dev/shm: a glTF buffer)
	// stays within them, and an input over a limit is refused, not an OOM.
	ihf::MeshImportLimits limits;
	limits.maxFileBytes = 1u << 20;
	limits.maxVertices = 1u << 20;
	limits.maxTriangles = 1u << 20;
	auto mesh = ihf::loadMesh(path, limits);
	if (mesh) {
		// A loaded mesh is what training needs: triangles, each index a
		// vertex, finite coordinates, no degenerate face.
		if (mesh->faces.empty())
			__builtin_trap();
		for (const auto &v : mesh->vertices)
			if (!v.allFinite())
				__builtin_trap();
		for (const auto &f : mesh->faces) {
			for (uint32_t v : f)
				if (v >= mesh->vertices.size())
					__builtin_trap();
			if (ihf::isDegenerateFace(*mesh, f))
				__builtin_trap();
		}
	}
	return 0;
}
