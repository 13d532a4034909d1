// SPDX-License-Identifier: MIT
#pragma once

// Finds an object's near-symmetries (near_symmetry.h) from its own views.
// Candidate axes are the principal axes of the surface through its centroid
// and the model frame's x, y, z through its box centre; each is first moved
// to where its half-turn moves the least surface off the surface (the mesh
// sampled evenly by area; a search over the plane square to the axis round
// the box centre, then a point-to-plane least-squares fit). Each turn by a
// multiple of stepDeg is then looked at as the estimator sees it: depth
// views from all round the object, plain and turned, compared pixel by
// pixel (turn_views.h). An axis whose every turn changes at most maxShare of
// the pixels (mean over the views) is continuous; otherwise each turn that
// does is a discrete near-symmetry. Each says in how many of the views it
// looks alike (alikeViews). A turn that changes (almost) nothing is a true
// symmetry and is kept too, with its share near 0.
// Deterministic (a fixed sample sequence and fixed views); training time,
// allocates.

#include <string>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/model/near_symmetry.h"
#include "core/training/turn_views.h"

namespace ihf {

struct NearSymmetryConfig {
	int samples = 3000;       // surface samples
	float stepDeg = 30;       // turns tried: multiples of this
	float matchShare = 0.02f; // placing an axis: a turned sample within this share of the diameter lies on the surface
	float maxShare = 0.35f;   // at most this share of the pixels may differ (mean over the views)
	TurnViewsConfig views;
	int maxFound = 6;         // near-symmetries kept, the smallest shares first
};

std::vector<NearSymmetry> findNearSymmetries(const Mesh &mesh, const NearSymmetryConfig &config = {});

// One line for the training log: "a turn by 180 deg about (1.000, 0.000,
// 0.000) through (...) mm: 44.7 % of the pixels differ, alike in 31 % of the
// views".
std::string describeNearSymmetry(const NearSymmetry &s);

} // namespace ihf
