// SPDX-License-Identifier: MIT
// PLY meshes (ihf train, ihf render, BOP models): loadPly.

#include "core/geometry/ply_loader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	auto mesh = ihf::loadPly(ihf::fuzz::inputFile(data, size, "mesh.ply"));
	if (mesh) {
		// A loaded mesh is usable: every face index names a vertex.
		for (const auto &f : mesh->faces)
			for (uint32_t v : f)
				if (v >= mesh->vertices.size())
					__builtin_trap();
	}
	return 0;
}
