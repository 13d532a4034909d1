// SPDX-License-Identifier: MIT
#pragma once

// One BOP scene as a recording: its depth images in image-id order become
// the frames (frame index = image id, core/dataset/bop_frames.h, which
// `ihf eval --run-poses` maps back; BOP has no timestamps, so frame n,
// 0-based, gets device and host timestamps n / fps), the intrinsics and
// depth scale come from scene_camera.json. A recording has one camera, so a
// scene whose cam_K or depth_scale changes between images is refused. With
// boxes given, the scene's detections are also written as `ihf run` box
// lines, one line per recorded image. Used by `ihf record --from-bop` and by
// `ihf synth --sequence`.

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/common/expected.h"

namespace ihf {

struct BopRecordingRequest {
	std::filesystem::path dataset;
	std::string split;  // empty: test, val or train, the first present
	int sceneId = -1;   // < 0: the split's only scene
	std::filesystem::path out;
	double fps = 30;
	bool compress = false;
	std::string sensorId; // empty: "bop:DATASET_NAME/SPLIT/SCENE"
	std::filesystem::path boxes;    // BOP detections; empty: no box lines
	std::filesystem::path boxesOut; // where the box lines go
};

struct BopRecordingResult {
	int sceneId = 0;
	int64_t frames = 0;
};

// Errors name the file at fault; kInvalidArgument when the request itself
// is incomplete (several scenes and none chosen).
Expected<BopRecordingResult> recordBopScene(const BopRecordingRequest &request);

} // namespace ihf
