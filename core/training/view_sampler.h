// SPDX-License-Identifier: MIT
#pragma once

// Training viewpoints (paper Sect. III-B: positive synthetic views): camera
// directions quasi-uniform over the view sphere (or a band of it), several
// in-plane rotations each, and a distance drawn from a range. The object
// origin sits on the optical axis; inference turns each crop into the same
// on-axis virtual camera, so offsets and rotations transfer.

#include <cstdint>
#include <vector>

#include "core/geometry/pose.h"

namespace ihf {

struct ViewSamplerConfig {
	int viewpoints = 320; // directions on the sphere
	int inplaneSteps = 6; // in-plane rotations per direction
	double minElevationDeg = -90; // lowest camera elevation over the model's xy plane
	double maxElevationDeg = 90;
	double minDistance = 600; // mm, camera to object origin
	double maxDistance = 1200;
	uint64_t seed = 1;
};

struct TrainingView {
	Pose pose; // model -> camera; pose.t = (0, 0, distance)
	int viewpoint = 0;
	int inplane = 0;
};

std::vector<TrainingView> sampleTrainingViews(const ViewSamplerConfig &config);

} // namespace ihf
