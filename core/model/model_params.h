// SPDX-License-Identifier: MIT
#pragma once

// Everything inference needs to know about how a forest was trained, stored
// beside it in the forest file: the descriptor settings must match exactly.

#include <cstdint>
#include <string>
#include <vector>

#include "core/features/depth_cloud.h"
#include "core/features/hocp.h"
#include "core/features/part.h"
#include "core/ibs/ibs_config.h"

namespace ihf {

struct ModelParams {
	int objId = 0;
	double diameter = 0; // mm, of the mesh
	bool symmetric = false;

	DepthCloudConfig cloud;
	IbsConfig ibs;
	PartConfig parts; // part kind and size at the initial registration
	HocpConfig hocp;
	float depthCheckMarginMm = 5.0f; // forest depth check margin

	// Provenance, for `ihf forest info`.
	std::vector<float> trainScales;
	int trainViews = 0;
	int trainSamples = 0;
	double trainSeconds = 0;
	uint64_t seed = 0;
	std::string meshName;
};

} // namespace ihf
