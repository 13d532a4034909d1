// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/pose_pipeline.h"

#include <string>

namespace ihf::app {

PosePipeline::PosePipeline(ForestSet forests, const EstimateSettings &settings, PacingClock &clock)
	: forests_(std::move(forests)), estimator_(settings.limits),
	  frames_(forests_.models(), estimator_, settings.estimator, clock)
{
}

Expected<std::unique_ptr<PosePipeline>> PosePipeline::create(const std::map<int, std::filesystem::path> &forests,
							     EstimateSettings &settings,
							     const TrackerConfig *tracking, PacingClock &clock,
							     const char *command)
{
	Expected<ForestSet> set = ForestSet::load(forests, settings, command);
	if (!set)
		return set.error();
	std::unique_ptr<PosePipeline> p(new PosePipeline(std::move(set.value()), settings, clock));
	if (!p->estimator_.valid())
		return makeError(Errc::kCapacity, "cannot allocate the estimator's arena of " +
							     std::to_string(PoseEstimator::arenaBytes(settings.limits)) +
							     " bytes");
	if (tracking) {
		p->tracker_ = std::make_unique<StreamEstimator>(p->estimator_, *tracking);
		if (!p->tracker_->valid())
			return makeError(Errc::kCapacity, "cannot allocate the tracker's arena");
		p->frames_.setTracker(p->tracker_.get());
	}
	return p;
}

} // namespace ihf::app
