// SPDX-License-Identifier: MIT
#pragma once

// Writes synthetic depth sequences as a BOP test set: ROOT/camera.json,
// ROOT/models/ (the targets' meshes), ROOT/test/SCENE/ with one scene per
// sequence (scene ids from 1, image id = frame index; scene_gt.json lists
// every visible target), ROOT/boxes.json (the simulated detector's boxes),
// ROOT/sequences.json (per scene: camera motion, targets, events, pauses)
// and ROOT/synth_config.json. Built in a hidden sibling folder and renamed
// into place at the end, so a failure leaves nothing at ROOT.

#include <filesystem>
#include <functional>
#include <vector>

#include "core/common/expected.h"
#include "core/synth/sequence_config.h"

namespace ihf {

struct SequenceSummary {
	int sequences = 0;
	int frames = 0;
	int instances = 0; // visible targets over all frames
	int boxes = 0;
	std::vector<double> secondsPerSequence;
	double seconds = 0;
};

// Called after every frame (for progress output).
using SequenceProgress = std::function<void(int sequenceId, int frame, int frames)>;

// Adds files derived from the finished BOP set (the recordings of `ihf synth
// --sequence`), per scene, before the set is moved into place: root is the
// staged dataset root.
using SequenceSceneHook = std::function<Status(const std::filesystem::path &root, int sceneId)>;

Expected<SequenceSummary> runSynthSequences(const SequenceConfig &config,
					    const SequenceProgress &progress = {},
					    const SequenceSceneHook &sceneHook = {});

} // namespace ihf
