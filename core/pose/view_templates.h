// SPDX-License-Identifier: MIT
#pragma once

// Sparse depth templates of an object: for each viewing direction of a
// Fibonacci lattice (the training views' layout), up to pointsPerView model
// points (mm, model frame) seen from a camera in that direction looking at
// the model's origin. A turn about the optical axis does not change what is
// visible, so one point set serves every in-plane rotation of its direction.
// Verifying a rotation at a translation then costs a few hundred point
// projections instead of a render (view_search.h). Non-owning: the points
// live in the forest file or in the model.

#include <span>

#include <Eigen/Core>

namespace ihf {

struct ViewTemplates {
	int viewpoints = 0;
	int pointsPerView = 0;
	// viewpoints x pointsPerView points; a view with fewer visible points
	// repeats its last one (a repeat counts twice, harmless for a score).
	std::span<const Eigen::Vector3f> points;
	// Optional: the viewpoints' unit directions (from the model's origin
	// towards the camera), so that finding the view nearest a pose needs no
	// trigonometry (view_search.h, nearestView); empty: computed on demand.
	std::span<const Eigen::Vector3f> directions = {};

	bool empty() const { return viewpoints <= 0 || pointsPerView <= 0 || points.empty(); }
	std::span<const Eigen::Vector3f> view(int v) const
	{
		return points.subspan(static_cast<size_t>(v) * pointsPerView, static_cast<size_t>(pointsPerView));
	}
};

} // namespace ihf
