// SPDX-License-Identifier: MIT
#pragma once

// The coarse 2D box a detector would hand over: the object's full (amodal)
// box enlarged by a random 5-25 % per axis, its centre shifted by up to 10 %
// of the box size per axis, clipped to the image.

#include <array>

#include "core/dataset/bop_types.h"
#include "core/synth/synth_random.h"

namespace ihf {

struct DetectionNoise {
	double growMin = 0.05, growMax = 0.25; // relative enlargement per axis
	double shiftMax = 0.10;                // relative centre shift per axis
	double scoreMin = 0.5, scoreMax = 1.0;
};

// bboxObj is x, y, w, h (may reach outside the image). time is 0: no
// detector ran.
Detection coarseDetection(const std::array<int, 4> &bboxObj, int imageWidth, int imageHeight,
			  int sceneId, int imageId, int objId, SynthRandom &rng,
			  const DetectionNoise &noise = {});

} // namespace ihf
