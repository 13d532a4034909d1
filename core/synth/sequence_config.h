// SPDX-License-Identifier: MIT
#pragma once

// What `ihf synth --sequence` is asked to produce: 30 Hz depth sequences of a
// cluttered table with several target objects and a moving camera, with the
// checks that turn a bad request into an error naming the option.

#include <filesystem>
#include <vector>

#include "core/common/expected.h"
#include "core/synth/camera_path.h"
#include "core/synth/scene_synthesizer.h"
#include "core/synth/sequence_detector.h"

namespace ihf {

struct SequenceParams {
	// Seed, table and clutter (layout), sensor model, depth scale. The
	// occlusion options of single images do not apply.
	SynthParams synth;
	int frames = 300;
	double fps = 30;
	int perFrameMin = 3, perFrameMax = 8; // target objects on the table
	CameraMotion motion = CameraMotion::kMixed;
	// Speed limits, distance, elevation, pauses (style and duration are set
	// per sequence).
	CameraPathParams path;
	// Probability that, besides the move, one object is taken away or a new
	// one put down.
	double changeProbability = 0.5;
	double carrySecondsMin = 0.8, carrySecondsMax = 1.2;
	double targetGapMax = 50; // mm between a target and the one it is placed beside
	// Share of targets placed in line with their neighbour along the
	// camera's base direction (they hide each other as the view swings).
	double inLineProbability = 0.7;
	double groupRadius = 260; // mm: targets stand this near the first, new places this near their mean
	DetectorParams detector;
	bool keepClean = false; // keep the clean render in each frame (tests)
};

struct SequenceConfig {
	std::filesystem::path modelsDir;
	std::vector<int> objects; // the targets a sequence draws from
	int sequences = 1;
	std::filesystem::path outDir;
	std::filesystem::path cameraFile; // empty: Kinect v1 default
	SequenceParams params;
	bool overwrite = false;
};

// Range and consistency checks of everything that does not need the disk.
Status validateSequenceConfig(const SequenceConfig &config);

} // namespace ihf
