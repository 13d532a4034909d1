// SPDX-License-Identifier: MIT
#pragma once

// `ihf run --vis DIR`: for every box, one PNG per iteration (as the paper's
// Fig. 9) of the box's depth crop (grey, near = bright) with the silhouette
// of that iteration's best-scoring hypothesis rendered over it (red, the
// outline brighter), plus the final pose (green):
//   DIR/f<frame>_o<obj>_it<k>.png, DIR/f<frame>_o<obj>_final.png
// Hypotheses come from the estimator's observer; the picture is drawn after
// the estimate, so the estimate itself is not slowed by more than the
// bookkeeping. Debugging only: drawing allocates.

#include <filesystem>
#include <memory>
#include <vector>

#include "core/estimation/pose_estimator.h"
#include "firmware_app/runtime/frame_estimator.h"

namespace ihf::app {

class VisWriter : public EstimateObserver, public BoxObserver
{
public:
	static Expected<std::unique_ptr<VisWriter>> create(const std::filesystem::path &dir,
							   const EstimatorLimits &limits);

	void onHypothesis(const HypothesisEvent &event) override;
	void begin(uint64_t frame, int objId, const PixelBox &box, ImageView<const float> depthMm,
		   const CameraIntrinsics &K, const ObjectModel &model) override;
	void end(ImageView<const float> depthMm, const CameraIntrinsics &K, const ObjectModel &model,
		 const PoseEstimate &estimate) override;

	uint64_t written() const { return written_; }
	// The first write failure, if any (the run goes on without pictures).
	const std::string &failure() const { return failure_; }

private:
	struct Best {
		bool valid = false;
		float score = 0;
		Pose pose;
	};

	VisWriter() = default;
	bool draw(ImageView<const float> depthMm, const CameraIntrinsics &K, const ObjectModel &model,
		  const Pose &pose, const uint8_t colour[3], const std::filesystem::path &file);

	std::filesystem::path dir_;
	DepthRenderer renderer_;
	uint64_t frame_ = 0;
	int objId_ = 0;
	PixelBox box_;
	std::vector<Best> best_; // per iteration
	std::vector<float> render_;
	std::vector<uint8_t> rgb_;
	uint64_t written_ = 0;
	std::string failure_;
};

} // namespace ihf::app
