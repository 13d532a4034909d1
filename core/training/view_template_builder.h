// SPDX-License-Identifier: MIT
#pragma once

// Builds the view templates of a mesh (view_templates.h): one render per
// viewing direction, and up to pointsPerView visible points sampled evenly
// over the silhouette's interior (pixels at depth edges are left out: a
// sensor loses or smears them). Allocates: run when a forest is loaded
// (the templates are not stored in the forest file), never per frame.

#include <vector>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf {

struct ViewTemplateConfig {
	int viewpoints = 320;
	int budgetViewpoints = 120; // when the estimator runs inside a frame budget
	int pointsPerView = 128;
};

// viewpoints x pointsPerView model points (mm), view by view.
Expected<std::vector<Eigen::Vector3f>> buildViewTemplatePoints(const Mesh &mesh, double diameter,
							       const ViewTemplateConfig &config);

} // namespace ihf
