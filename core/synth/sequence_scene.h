// SPDX-License-Identifier: MIT
#pragma once

// The plan of one synthetic sequence, drawn before any frame is rendered: a
// table with several target objects standing close together (so they hide
// each other as the view changes) among clutter, the camera's path around
// it, what happens to the targets (one is picked up and set down elsewhere;
// perhaps one is taken away or a new one put down) and which frames the
// detector misses each target in. The frames then only evaluate the plan
// at their time, each with its own random stream for the sensor and boxes.

#include <cstdint>
#include <vector>

#include "core/common/expected.h"
#include "core/synth/camera_path.h"
#include "core/synth/model_library.h"
#include "core/synth/object_schedule.h"
#include "core/synth/scene_layout.h"
#include "core/synth/sequence_config.h"

namespace ihf {

struct TargetSlot {
	int objId = 0;
	ObjectSchedule schedule;
	std::vector<uint8_t> misses; // per frame: the detector misses it
};

struct SequenceScene {
	int sequenceId = 0;
	uint64_t key = 0; // the sequence's random stream key (frames derive theirs)
	// targets.size() target objects first (at their first pose; the
	// schedules move them), then clutter, background, table slab and room.
	SceneLayout layout;
	std::vector<TargetSlot> targets;
	CameraPath path;
	Eigen::Vector3d centre = Eigen::Vector3d::Zero(); // where the camera looks around
	int attempts = 0;
};

// Draws the plan of sequence sequenceId (>= 1) from (seed, sequenceId):
// the same arguments give the same plan.
Expected<SequenceScene> planSequenceScene(const ModelLibrary &library, const CameraIntrinsics &K,
					  const SequenceParams &params,
					  const std::vector<int> &objects, int sequenceId);

} // namespace ihf
