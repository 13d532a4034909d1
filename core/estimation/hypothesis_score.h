// SPDX-License-Identifier: MIT
#pragma once

// Depth consistency of a pose hypothesis: its rendering compared with the
// observed depth pixel by pixel. Where the model is drawn and depth was
// observed, the pixel is an inlier (within inlierMm), occluded (observed in
// front: something covers the object, which is allowed) or an outlier
// (observed behind: the object would hide what the sensor saw, so the pose
// is wrong there). The score in [0, 1] rewards inliers, punishes outliers
// fully and occlusion half, so a correct pose of a 60% occluded object still
// scores well above a pose floating in front of the scene.

#include "core/common/image.h"

namespace ihf {

struct ScoreConfig {
	float inlierMm = 10.0f;
	float occludedWeight = 0.5f;
};

struct HypothesisScore {
	int rendered = 0;  // model pixels
	int compared = 0;  // model pixels with observed depth
	int inliers = 0;
	int outliers = 0;
	int occluded = 0;
	float score = 0;
	float depthMin = 0; // rendered depth range (Eq. 10's gamma, beta)
	float depthMax = 0;
};

HypothesisScore scoreHypothesis(ImageView<const float> observed, ImageView<const float> rendered,
				const ScoreConfig &config);

} // namespace ihf
