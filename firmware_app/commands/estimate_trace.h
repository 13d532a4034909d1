// SPDX-License-Identifier: MIT
#pragma once

// `ihf estimate --trace`: every scored hypothesis as a JSON line, for
// diagnosing which stage loses a pose. Ground-truth poses of the box's
// object, when the dataset has them, are scored the same way (stage
// "given"); when it has none, a line of stage "no_truth" says why; the
// box's answer comes last (stage "result"). Vote lines give the share of
// the vote weight near each ground-truth pose: rotation within 20 deg,
// centre within 0.1 diameter, and both. Comparison lines (stage
// "comparison") give, for a nearly symmetric object, each rival the best was
// compared with on the pixels where their renders differ, and the pixels
// that spoke for each: what kept or replaced the best, and what left it
// certain or ambiguous.

#include <cstdio>
#include <string>
#include <vector>

#include "core/dataset/bop_types.h"
#include "core/estimation/pose_estimator.h"
#include "firmware_app/runtime/frame_estimator.h"

namespace ihf::app {

class EstimateTrace : public EstimateObserver, public BoxObserver
{
public:
	// Lines go to f; the ground truth is scored by estimator with config.
	EstimateTrace(std::FILE *f, PoseEstimator &estimator, const EstimatorConfig &config);

	// The scene of the boxes that follow, with its ground truth; noTruth:
	// why the scene has none ("" when it has).
	void setImage(int sceneId, const BopScene &scene, const std::string &noTruth);

	void begin(uint64_t frame, int objId, const PixelBox &box, ImageView<const float> depthMm,
		   const CameraIntrinsics &K, const ObjectModel &model) override;
	void end(ImageView<const float> depthMm, const CameraIntrinsics &K, const ObjectModel &model,
		 const PoseEstimate &estimate) override;
	void onVotes(const VoteEvent &e) override;
	void onHypothesis(const HypothesisEvent &e) override;
	void onComparison(const ComparisonEvent &e) override;

private:
	// No ground truth to compare this box with: no "given" lines and no vote
	// shares follow.
	void noTruth(const std::string &why);
	// A JSON string (reasons hold file paths).
	void writeString(const std::string &text);
	// "R":[9 numbers],"t":[3 numbers] of a trace line.
	void writePose(const Pose &p);

	std::FILE *f_;
	PoseEstimator &estimator_;
	const EstimatorConfig &config_;
	int sceneId_ = 0, image_ = 0, obj_ = 0;
	const BopScene *scene_ = nullptr;
	std::string sceneNoTruth_;
	double diameter_ = 0;
	std::vector<Pose> truth_;
};

} // namespace ihf::app
