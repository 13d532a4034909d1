// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/frame_estimator.h"

#include <cstdio>
#include <string>

#include "core/features/cloud_point.h"
#include "firmware_app/runtime/warm_up_note.h"

namespace ihf::app {

namespace {

// The answer of a box that is not estimated.
StreamResult notEstimated(const char *reason)
{
	StreamResult r;
	r.mode = BoxMode::kSkipped;
	r.estimate.reason = reason;
	return r;
}

} // namespace

FrameEstimator::FrameEstimator(const std::map<int, const ObjectModel *> &models, PoseEstimator &estimator,
			       const EstimatorConfig &config, PacingClock &clock)
	: models_(models), estimator_(estimator), config_(config), clock_(clock)
{
}

const ObjectModel *FrameEstimator::model(int objId) const
{
	const auto it = models_.find(objId);
	return it == models_.end() ? nullptr : it->second;
}

void FrameEstimator::warmUp(const CameraIntrinsics &K, const char *command)
{
	if (config_.frameBudgetMs <= 0)
		return;
	for (const auto &[id, model] : models_)
		if (const std::string note =
			    warmUpNote(id, estimator_.warmUp(*model, K, config_), config_.frameBudgetMs);
		    !note.empty())
			std::fprintf(stderr, "%s: %s\n", command, note.c_str());
}

void FrameEstimator::beginStream()
{
	if (tracker_)
		tracker_->reset();
}

void FrameEstimator::skipFrame(uint64_t frame, const CameraIntrinsics &K)
{
	if (tracker_)
		tracker_->estimateFrame(frame, {}, K, {}, config_, config_.frameBudgetMs, {});
}

Status FrameEstimator::estimate(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
				std::span<const FrameBox> boxes, BoxSink &sink)
{
	return tracker_ ? estimateTracked(frame, depthMm, K, boxes, sink)
			: estimateCold(frame, depthMm, K, boxes, sink);
}

Status FrameEstimator::estimateCold(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
				    std::span<const FrameBox> boxes, BoxSink &sink)
{
	// The frame's budget is shared by the boxes that have a forest.
	int estimated = 0;
	for (const FrameBox &b : boxes)
		estimated += model(b.objId) != nullptr;
	struct FrameScope {
		PoseEstimator &e;
		~FrameScope() { e.endFrame(); }
	} frameScope{estimator_};
	estimator_.beginFrame(estimated, config_.frameBudgetMs);
	for (const FrameBox &b : boxes) {
		const ObjectModel *m = model(b.objId);
		if (!m) {
			if (Status st = sink.onBox(b, nullptr, notEstimated("no forest for the object")); !st)
				return st;
			continue;
		}
		const PixelBox box = pixelsOfBox(b.bbox);
		if (observer_)
			observer_->begin(frame, b.objId, box, depthMm, K, *m);
		StreamResult r;
		r.mode = BoxMode::kDetect;
		r.startNs = clock_.nowNs();
		r.estimate = estimator_.estimate(depthMm, K, box, *m, config_);
		r.ns = clock_.nowNs() - r.startNs;
		if (observer_)
			observer_->end(depthMm, K, *m, r.estimate);
		if (Status st = sink.onBox(b, m, r); !st)
			return st;
	}
	return {};
}

Status FrameEstimator::estimateTracked(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
				       std::span<const FrameBox> boxes, BoxSink &sink)
{
	size_t n = 0;
	for (const FrameBox &b : boxes)
		if (const ObjectModel *m = model(b.objId); m && n < streamBoxes_.size())
			streamBoxes_[n++] = StreamBox{b.objId, pixelsOfBox(b.bbox), b.trackId, m};
	tracker_->estimateFrame(frame, depthMm, K, std::span<const StreamBox>(streamBoxes_.data(), n), config_,
				config_.frameBudgetMs, std::span<StreamResult>(streamResults_.data(), n));
	size_t next = 0;
	for (const FrameBox &b : boxes) {
		const ObjectModel *m = model(b.objId);
		Status st;
		if (!m)
			st = sink.onBox(b, nullptr, notEstimated("no forest for the object"));
		else if (next < n)
			st = sink.onBox(b, m, streamResults_[next++]);
		else
			st = sink.onBox(b, m, notEstimated("more boxes in the frame than the tracker holds"));
		if (!st)
			return st;
	}
	return {};
}

} // namespace ihf::app
