// SPDX-License-Identifier: MIT
#pragma once

// The frames of a synthetic depth sequence: each frame evaluates the
// sequence's plan (sequence_scene.h) at its time (targets where their
// schedules put them, the camera where its path is), renders the scene
// from the camera (and the projector), passes it through the sensor model
// and derives the ground truth of every visible target (pose, scene_gt_info
// entry) and the simulated detector's boxes. Every frame draws from its own
// random stream, seeded from (seed, sequence, frame), so a frame does not
// depend on the frames before it.

#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/dataset/bop_types.h"
#include "core/synth/model_library.h"
#include "core/synth/scene_render.h"
#include "core/synth/sequence_config.h"
#include "core/synth/sequence_scene.h"

namespace ihf {

struct SequenceFrame {
	DepthImage16 depth; // sensor depth, raw units of depthScale
	Pose worldToCamera;
	// Every target with at least one visible pixel, by object id.
	std::vector<GtInstance> gt;
	std::vector<GtInfo> info; // parallel to gt
	std::vector<Detection> detections;
	// Only with keepClean: clean depth (mm), labels and the label of each gt.
	DepthImageMm cleanDepth;
	Image<uint16_t> cleanLabel;
	std::vector<uint16_t> gtLabel;
};

class SequenceSynthesizer
{
public:
	// objects: the target ids sequences draw from (all in library).
	SequenceSynthesizer(const ModelLibrary &library, const CameraIntrinsics &K,
			    SequenceParams params, std::vector<int> objects);

	Expected<SequenceScene> plan(int sequenceId) const;
	Expected<SequenceFrame> frame(const SequenceScene &scene, int frameIndex);

	const SequenceParams &params() const { return params_; }
	const CameraIntrinsics &intrinsics() const { return K_; }

private:
	const ModelLibrary &library_;
	CameraIntrinsics K_;
	SequenceParams params_;
	std::vector<int> objects_;
	SceneRenderer renderer_;
	int projectorPad_ = 0;
	DepthImageMm depth_;
	Image<uint16_t> label_;
	DepthImageMm projector_;
};

} // namespace ihf
