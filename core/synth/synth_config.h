// SPDX-License-Identifier: MIT
#pragma once

// What `ihf synth` is asked to produce, with the checks that turn a bad
// request into a clear error before anything is written.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/common/expected.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/synth/scene_synthesizer.h"

namespace ihf {

struct SynthConfig {
	std::filesystem::path modelsDir;
	std::vector<int> objects;
	int images = 50;
	std::filesystem::path outDir;
	std::filesystem::path cameraFile; // empty: Kinect v1 default
	SynthParams params;               // seed, ranges, scene and sensor models
	std::filesystem::path previewDir; // empty: no pictures
	int previewCount = 4;             // pictures per object
	bool overwrite = false;
};

// "a:b" with a <= b (or a single value "a" meaning a:a). flag names the
// option in the error message.
Expected<std::pair<double, double>> parseRange(const std::string &text, const std::string &flag);

// "1,5,6": positive, distinct ids.
Expected<std::vector<int>> parseIdList(const std::string &text, const std::string &flag);

// Range and consistency checks of everything that does not need the disk.
Status validateConfig(const SynthConfig &config);

} // namespace ihf
