// SPDX-License-Identifier: MIT
#pragma once

// Reads the JSON lines `ihf run` writes (firmware_app/runtime/pose_output.h), for
// comparing them with ground truth:
//
//   pose:  {"frame": F, "obj_id": O, "R": [9 numbers, row-major], "t": [x, y, z], ...}
//   error: {"frame": F, "obj_id": O, "error": "..."}   (frame, obj_id optional)
//
// Other fields are ignored and blank lines skipped. A line that is not one
// of the two fails the read with an error naming the file and line (not
// JSON, a missing field, a frame that is not a non-negative integer, an
// obj_id that is not a positive integer, R not 9 or t not 3 numbers).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/geometry/pose.h"

namespace ihf {

struct RunPoseLine {
	size_t line = 0; // 1-based line number in the file
	std::optional<uint64_t> frame; // always set for a pose
	std::optional<int> objId;      // always set for a pose
	std::optional<Pose> pose;      // absent: an error line
	std::string error;             // an error line's message
};

Expected<std::vector<RunPoseLine>> readRunPoses(const std::filesystem::path &file);

} // namespace ihf
