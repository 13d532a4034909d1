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

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const auto path = ihf::fuzz::inputFile(data, size, nameFor(data, size));
	auto mesh = ihf::loadMesh(path);
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
