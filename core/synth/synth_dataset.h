// SPDX-License-Identifier: MIT
#pragma once

// Writes a synthetic BOP test set: ROOT/camera.json, ROOT/models/ (the
// targets' meshes and models_info.json), ROOT/test/SCENE/ with one scene per
// target (scene id = object id, as LINEMOD), ROOT/boxes.json (one coarse
// detection per image) and ROOT/synth_config.json (how it was made). The set
// is built in a hidden sibling folder and renamed into place at the end, so
// a failure leaves nothing at ROOT.

#include <functional>
#include <vector>

#include "core/common/expected.h"
#include "core/synth/synth_config.h"

namespace ihf {

struct SynthSummary {
	int images = 0;
	std::vector<double> occlusion; // 1 - visib_fract per image
	std::vector<int> objectOf;     // object id per image
	int attemptsTotal = 0;
	int occludersTotal = 0;
	int truncated = 0; // images where the border cuts > 1 % of the target
	double seconds = 0;
};

// Called after every image (for progress output).
using SynthProgress = std::function<void(int objId, int imageId, int done, int total,
					 const SynthImage &image)>;

Expected<SynthSummary> runSynth(const SynthConfig &config, const SynthProgress &progress = {});

} // namespace ihf
