// SPDX-License-Identifier: MIT
#pragma once

// Finds an object's near-symmetries (near_symmetry.h) from its surface: the
// mesh is sampled evenly by area, and for candidate axes (the principal axes
// of the samples through their centroid, and the model frame's x, y, z
// through its box centre) each turn by a multiple of stepDeg is applied to
// the samples. A turned sample that lands on the surface (a sample within
// matchMm whose normal agrees, measured along that normal) is explained; the
// share that is not is how much the turn changes the object. Each axis is
// first moved to where its half-turn moves the least surface off the
// surface (a search over the plane square to it round the box centre, then
// a point-to-plane least-squares fit). An axis whose every turn leaves at most
// maxShare unexplained is continuous; otherwise each turn that does is a
// discrete near-symmetry. A turn that explains (almost) everything is a
// true symmetry and is kept too, with its share near 0.
// Deterministic (a fixed sample sequence); training time, allocates.

#include <vector>

#include "core/geometry/mesh.h"
#include "core/model/near_symmetry.h"

namespace ihf {

struct NearSymmetryConfig {
	int samples = 3000;       // surface samples
	float stepDeg = 30;       // turns tried: multiples of this
	float matchShare = 0.02f; // a turned sample within this share of the diameter lies on the surface
	float maxShare = 0.3f;    // at most this share of the surface may differ
	int maxFound = 6;         // near-symmetries kept, the smallest shares first
};

std::vector<NearSymmetry> findNearSymmetries(const Mesh &mesh, const NearSymmetryConfig &config = {});

} // namespace ihf
