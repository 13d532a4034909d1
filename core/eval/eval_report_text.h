// SPDX-License-Identifier: MIT
#pragma once

// The reports of `ihf eval` as plain-text tables.

#include <string>

#include "core/eval/evaluation.h"
#include "core/eval/run_pose_check.h"

namespace ihf {

// One row per object (metric, diameter, counts, F1 per z, mean F1, recall
// at 0.1 Phi, median time) and a final row of means over objects.
std::string formatEvalTable(const EvalReport &report);

// One row per line of `ihf run` (line, frame, scene, image, object,
// rotation and translation error, metric, error / diameter, right or wrong,
// or why there is nothing to compare), then a summary line: how many poses
// were right, and the median and largest rotation and translation errors.
std::string formatRunPoseTable(const RunPoseReport &report);

} // namespace ihf
