// SPDX-License-Identifier: MIT
#include "benchmarks/peers/model_sampler.h"

#include <algorithm>
#include <random>
#include <string>

#include <Eigen/Geometry>

namespace ihf::peers {

Expected<PeerModel> sampleModel(const Mesh &mesh, int objId, double diameter, int count,
				uint32_t seed)
{
	std::vector<double> cumArea;
	std::vector<size_t> faceOf;
	double total = 0;
	for (size_t f = 0; f < mesh.faces.size(); ++f) {
		const auto &idx = mesh.faces[f];
		if (idx[0] >= mesh.vertices.size() || idx[1] >= mesh.vertices.size() ||
		    idx[2] >= mesh.vertices.size())
			return makeError(Errc::kCorrupt, "object " + std::to_string(objId) + ": face " +
								  std::to_string(f) + " indexes past the vertices");
		const Eigen::Vector3f &a = mesh.vertices[idx[0]];
		double area = 0.5 * (mesh.vertices[idx[1]] - a).cross(mesh.vertices[idx[2]] - a).norm();
		if (area <= 1e-12)
			continue;
		total += area;
		cumArea.push_back(total);
		faceOf.push_back(f);
	}
	if (cumArea.empty())
		return makeError(Errc::kInvalidArgument,
				 "object " + std::to_string(objId) + ": mesh has no face with an area");

	PeerModel model;
	model.objId = objId;
	model.diameter = diameter > 0 ? diameter : meshDiameter(mesh);
	model.points.reserve(count);
	model.normals.reserve(count);
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> uni(0.0, 1.0);
	for (int i = 0; i < count; ++i) {
		double r = uni(rng) * total;
		size_t k = std::lower_bound(cumArea.begin(), cumArea.end(), r) - cumArea.begin();
		const auto &idx = mesh.faces[faceOf[std::min(k, faceOf.size() - 1)]];
		const Eigen::Vector3f &a = mesh.vertices[idx[0]];
		const Eigen::Vector3f &b = mesh.vertices[idx[1]];
		const Eigen::Vector3f &c = mesh.vertices[idx[2]];
		// Uniform barycentric sample.
		float s = static_cast<float>(std::sqrt(uni(rng)));
		float t = static_cast<float>(uni(rng));
		Eigen::Vector3f p = (1 - s) * a + s * (1 - t) * b + s * t * c;
		// BOP meshes wind counter-clockwise seen from outside.
		Eigen::Vector3f n = (b - a).cross(c - a).normalized();
		model.points.push_back(p);
		model.normals.push_back(n);
	}
	return model;
}

} // namespace ihf::peers
