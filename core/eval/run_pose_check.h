// SPDX-License-Identifier: MIT
#pragma once

// `ihf eval --run-poses`: how close each pose line of `ihf run` came to the
// ground truth of the BOP scene its recording was made from (`ihf record
// --from-bop`; frames map back to images as core/dataset/bop_frames.h).
//
// - Each pose is compared with the instance of its object in its image that
//   it comes closest to (ADD, or ADI for symmetric objects, as `ihf eval`
//   decides: eval_dataset.h), over every vertex of the model.
// - Rotation error: the angle of R_est^T R_gt in degrees; translation error:
//   |t_est - t_gt| in millimetres; the ADD/ADI error as a share of the
//   object's diameter, right when <= `threshold` (0.1 d, ADD(-S)-0.1d).
// - An error line of the run is "no pose", with its message. A frame that
//   was not recorded from the scene, or an object without ground truth in
//   its image, is "no truth", with a message naming the file and line; the
//   comparison goes on.
// - Failures (the scene or its scene_gt.json, a model or models_info.json
//   entry of an object with ground truth) name the file at fault.

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/dataset/bop_dataset.h"
#include "core/eval/evaluation.h"
#include "core/eval/run_poses.h"

namespace ihf {

struct RunPoseRequest {
	int sceneId = -1; // < 0: the split's only scene
	std::filesystem::path posesFile; // named in messages
	double threshold = kRecallZ; // right when the error is at most this share of the diameter
};

enum class RunPoseVerdict {
	kRight,
	kWrong,
	kNoPose,  // an error line of the run
	kNoTruth, // no ground truth for its frame and object
};

struct RunPoseCheck {
	size_t line = 0;
	std::optional<uint64_t> frame;
	std::optional<int> objId;
	int sceneId = -1; // -1: the frame is not an image of the scene
	int imageId = -1;
	RunPoseVerdict verdict = RunPoseVerdict::kNoTruth;
	std::string note; // no pose: the run's message; no truth: why
	// Compared poses (right or wrong) only:
	PoseMetric metric = PoseMetric::kAdd;
	double rotationDeg = 0;
	double translationMm = 0;
	double errorMm = 0; // ADD or ADI
	double errorShare = 0; // errorMm / diameter
};

struct RunPoseReport {
	int sceneId = 0;
	double threshold = kRecallZ;
	std::vector<RunPoseCheck> checks; // one per line, in file order
};

// The comparison of one pose with the instances of its object in its image
// (at least one); fills the metric, errors and right/wrong.
void comparePose(const Pose &estimate, std::span<const Pose> truths, const EvalObject &object,
		 double threshold, RunPoseCheck &check);

Expected<RunPoseReport> checkRunPoses(const BopDataset &dataset, const std::vector<RunPoseLine> &lines,
				      const RunPoseRequest &request);

} // namespace ihf
