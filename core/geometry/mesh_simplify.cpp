// SPDX-License-Identifier: MIT
#include "core/geometry/mesh_simplify.h"

#include <vector>

#include <meshoptimizer.h>

namespace ihf {

Expected<SimplifiedMesh> simplifyMesh(const Mesh &mesh, float maxErrorMm)
{
	if (!(maxErrorMm > 0))
		return makeError(Errc::kInvalidArgument, "simplifyMesh: the error bound must be positive");
	if (mesh.vertices.empty() || mesh.faces.empty())
		return makeError(Errc::kInvalidArgument, "simplifyMesh: empty mesh");
	const size_t nv = mesh.vertices.size();
	std::vector<unsigned> indices;
	indices.reserve(mesh.faces.size() * 3);
	for (const auto &f : mesh.faces)
		for (uint32_t i : f) {
			if (i >= nv)
				return makeError(Errc::kInvalidArgument, "simplifyMesh: face index out of range");
			indices.push_back(i);
		}
	const float *positions = mesh.vertices.front().data();
	constexpr size_t kStride = sizeof(Eigen::Vector3f);
	// Vertices repeated along colour or normal seams would be borders the
	// simplifier must not move: weld them by position first.
	std::vector<unsigned> welded(indices.size());
	meshopt_generateShadowIndexBuffer(welded.data(), indices.data(), indices.size(), positions,
					  nv, kStride, kStride);
	const float scale = meshopt_simplifyScale(positions, nv, kStride);
	std::vector<unsigned> kept(welded.size());
	float relError = 0;
	const size_t n = meshopt_simplify(kept.data(), welded.data(), welded.size(), positions, nv, kStride,
					  /*target_index_count=*/0, maxErrorMm / scale, /*options=*/0, &relError);
	// Keep only the vertices the kept faces use, in first-use order.
	std::vector<int> remap(nv, -1);
	SimplifiedMesh out;
	out.errorMm = relError * scale;
	out.mesh.faces.reserve(n / 3);
	for (size_t i = 0; i + 2 < n; i += 3) {
		std::array<uint32_t, 3> f{};
		for (int k = 0; k < 3; ++k) {
			int &r = remap[kept[i + k]];
			if (r < 0) {
				r = static_cast<int>(out.mesh.vertices.size());
				out.mesh.vertices.push_back(mesh.vertices[kept[i + k]]);
				if (mesh.hasNormals())
					out.mesh.normals.push_back(mesh.normals[kept[i + k]]);
			}
			f[k] = static_cast<uint32_t>(r);
		}
		out.mesh.faces.push_back(f);
	}
	if (out.mesh.faces.empty())
		return makeError(Errc::kInvalidArgument, "simplifyMesh: nothing left of the mesh");
	return out;
}

} // namespace ihf
