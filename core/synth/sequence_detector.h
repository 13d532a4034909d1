// SPDX-License-Identifier: MIT
#pragma once

// A simulated 2D detector over a depth sequence. Per frame it boxes every
// target object at least minVisibFract visible, with the jitter of
// coarseDetection (detection_box.h); nothing for objects out of view or
// hidden. Now and then it misses an object: misses come in short runs, as
// a real detector loses an object for a few frames when its look changes
// (a two-state chain per object: a miss persists to the next frame with
// missPersistence; it starts with the rate that makes the long-run share
// of missed frames missProbability).

#include <cstdint>
#include <optional>
#include <vector>

#include "core/dataset/bop_types.h"
#include "core/synth/detection_box.h"
#include "core/synth/synth_random.h"

namespace ihf {

struct DetectorParams {
	DetectionNoise noise;
	double missProbability = 0.03; // long-run share of missed boxes
	double missPersistence = 0.5;  // a miss lasts 1 / (1 - this) frames on average
	double minVisibFract = 0.1;    // less visible objects get no box
};

// Which frames the detector misses one object in (1 = missed).
std::vector<uint8_t> detectorMisses(int frames, const DetectorParams &params, SynthRandom &rng);

// The box of one object in one frame, or nullopt when it is missed or too
// little of it is visible.
std::optional<Detection> detectObject(const GtInfo &info, bool missed, int imageWidth,
				      int imageHeight, int sceneId, int imageId, int objId,
				      SynthRandom &rng, const DetectorParams &params);

} // namespace ihf
