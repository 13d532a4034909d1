// SPDX-License-Identifier: MIT
#pragma once

// What `ihf estimate` and `ihf run` build from their settings, built in
// this one place: the forests of the given objects (ForestSet), the
// estimator sized for all of them, the tracker when frames are a stream,
// and the per-frame path over them (FrameEstimator).

#include <filesystem>
#include <map>
#include <memory>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"
#include "core/tracking/stream_estimator.h"
#include "drivers/clock.h"
#include "firmware_app/config/pipeline_config.h"
#include "firmware_app/runtime/forest_set.h"
#include "firmware_app/runtime/frame_estimator.h"

namespace ihf::app {

class PosePipeline
{
public:
	// Loads the forests (settings.limits grow to hold them) and allocates
	// the estimator's arena, and the tracker's when tracking is given (null:
	// every box a cold estimate). Notes and errors name `command`.
	static Expected<std::unique_ptr<PosePipeline>> create(const std::map<int, std::filesystem::path> &forests,
							      EstimateSettings &settings,
							      const TrackerConfig *tracking, PacingClock &clock,
							      const char *command);
	PosePipeline(const PosePipeline &) = delete;
	PosePipeline &operator=(const PosePipeline &) = delete;

	FrameEstimator &frames() { return frames_; }
	PoseEstimator &estimator() { return estimator_; }
	// Null without tracking.
	StreamEstimator *tracker() { return tracker_.get(); }
	const ForestSet &forests() const { return forests_; }

private:
	PosePipeline(ForestSet forests, const EstimateSettings &settings, PacingClock &clock);

	ForestSet forests_;
	PoseEstimator estimator_;
	std::unique_ptr<StreamEstimator> tracker_;
	FrameEstimator frames_;
};

} // namespace ihf::app
