// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/pose_stage.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ihf::app {

PoseStage::PoseStage(FrameEstimator &frames, BoxFeed &feed, PoseOutput &output, PacingClock &clock,
		     std::chrono::milliseconds boxesTimeout)
	: frames_(frames), feed_(feed), output_(output), clock_(clock), boxesTimeout_(boxesTimeout)
{
}

Status PoseStage::prepare(const SourceInfo &info)
{
	const CameraIntrinsics &k = info.intrinsics;
	if (k.width <= 0 || k.height <= 0)
		return makeError(Errc::kInvalidArgument, info.uri + ": source reports no frame size");
	if (depthMm_.width() != k.width || depthMm_.height() != k.height)
		depthMm_ = Image<float>(k.width, k.height);
	frames_.warmUp(k, "ihf run");
	return {};
}

Status PoseStage::process(const Frame &frame, int64_t arrivalNs)
{
	++counters_.frames;
	Expected<BoxWait> waited = feed_.wait(frame.index, boxesTimeout_);
	if (!waited)
		return waited.error();
	for (const std::string &problem : feed_.problems()) {
		++counters_.inputErrors;
		if (Status st = output_.writeError(-1, -1, problem); !st)
			return st;
	}
	if (*waited == BoxWait::kShutdown) {
		interrupted_ = true;
		return {};
	}
	if (*waited != BoxWait::kBoxes || feed_.boxes().empty()) {
		++counters_.framesWithoutBoxes;
		// A frame the detector saw nothing in ages the tracks, as in
		// ihf estimate --sequence.
		if (*waited == BoxWait::kBoxes)
			frames_.skipFrame(frame.index, frame.intrinsics);
		return {};
	}

	const ImageView<const uint16_t> raw = frame.depth;
	if (raw.width != depthMm_.width() || raw.height != depthMm_.height())
		return makeError(Errc::kInvalidArgument, "frame " + std::to_string(frame.index) +
								 ": size differs from the source's");
	// As BopDataset::loadDepthMm: raw * scale in double, then float.
	for (int y = 0; y < raw.height; ++y) {
		const uint16_t *src = raw.row(y);
		float *dst = depthMm_.view().row(y);
		for (int x = 0; x < raw.width; ++x)
			dst[x] = static_cast<float>(src[x] * frame.depthScale);
	}
	CameraIntrinsics K = frame.intrinsics;
	K.width = raw.width;
	K.height = raw.height;
	frame_ = frame.index;
	arrivalNs_ = arrivalNs;
	return frames_.estimate(frame.index, depthMm_.view(), K, feed_.boxes(), *this);
}

Status PoseStage::onBox(const FrameBox &box, const ObjectModel *model, const StreamResult &r)
{
	++counters_.boxes;
	if (!model)
		return writeUnknownObject(frame_, box.objId);
	if (!frames_.tracker())
		return writeResult(frame_, box.objId, r.estimate, r.ns * 1e-6, arrivalNs_, nullptr, 0);
	if (r.mode == BoxMode::kDeferred)
		++counters_.deferred;
	if (r.mode == BoxMode::kDeferred && !r.provisional)
		return output_.writeError(static_cast<int64_t>(frame_), box.objId,
					  "deferred: waits for a detection in a later frame", boxModeName(r.mode),
					  r.trackId);
	return writeResult(frame_, box.objId, r.estimate, r.ns * 1e-6, arrivalNs_, boxModeName(r.mode), r.trackId);
}

Status PoseStage::writeUnknownObject(uint64_t frame, int objId)
{
	++counters_.unknownObject;
	char msg[64];
	std::snprintf(msg, sizeof(msg), "no forest for object %d", objId);
	return output_.writeError(static_cast<int64_t>(frame), objId, msg);
}

Status PoseStage::writeResult(uint64_t frame, int objId, const PoseEstimate &e, double estimateMs,
			      int64_t arrivalNs, const char *mode, int trackId)
{
	if (!e.found) {
		++counters_.noPose;
		char msg[160];
		std::snprintf(msg, sizeof(msg), "no pose: %s", e.reason);
		return mode ? output_.writeError(static_cast<int64_t>(frame), objId, msg, mode, trackId)
			    : output_.writeError(static_cast<int64_t>(frame), objId, msg);
	}
	++counters_.poses;
	PoseLine line;
	line.frame = frame;
	line.objId = objId;
	line.estimate = &e;
	line.estimateMs = estimateMs;
	line.latencyMs = (clock_.nowNs() - arrivalNs) * 1e-6;
	line.mode = mode;
	line.trackId = trackId;
	latencies_[latencyCount_++ % latencies_.size()] = line.latencyMs;
	return output_.writePose(line);
}

void PoseStage::describe(std::string &line) const
{
	char buf[256];
	std::snprintf(buf, sizeof(buf), "; boxes %llu poses %llu no-pose %llu unknown-object %llu input-errors %llu",
		      static_cast<unsigned long long>(counters_.boxes),
		      static_cast<unsigned long long>(counters_.poses),
		      static_cast<unsigned long long>(counters_.noPose),
		      static_cast<unsigned long long>(counters_.unknownObject),
		      static_cast<unsigned long long>(counters_.inputErrors));
	line += buf;
	const StreamEstimator *tracker = frames_.tracker();
	if (tracker) {
		const TrackingStats &t = tracker->stats();
		std::snprintf(buf, sizeof(buf),
			      "; tracking: tracked %llu detected %llu (re-detected %llu) deferred %llu (provisional %llu) "
			      "forced %llu duplicates %llu tracks started %llu lost %llu",
			      static_cast<unsigned long long>(t.tracked), static_cast<unsigned long long>(t.detected),
			      static_cast<unsigned long long>(t.redetected), static_cast<unsigned long long>(t.deferred),
			      static_cast<unsigned long long>(t.provisional), static_cast<unsigned long long>(t.forced),
			      static_cast<unsigned long long>(t.duplicates),
			      static_cast<unsigned long long>(t.started), static_cast<unsigned long long>(t.lost));
		line += buf;
	}
	const float budgetMs = frames_.config().frameBudgetMs;
	const PoseEstimator &estimator = frames_.estimator();
	if (budgetMs > 0) {
		// What the device's frame budget cost: the same counts as ihf estimate's.
		const EstimatorStats st = estimator.stats();
		std::snprintf(buf, sizeof(buf),
			      "; budget %g ms: overruns %llu frames %llu boxes (%llu in the initial registration)"
			      " cut-short %llu iterations %llu tight %llu short %llu lean-search %llu worst-frame %.1f ms",
			      static_cast<double>(budgetMs),
			      static_cast<unsigned long long>(st.frameOverruns),
			      static_cast<unsigned long long>(st.boxOverruns),
			      static_cast<unsigned long long>(st.registrationOverruns),
			      static_cast<unsigned long long>(st.budgetStops),
			      static_cast<unsigned long long>(st.iterations),
			      static_cast<unsigned long long>(st.tightBoxes),
			      static_cast<unsigned long long>(st.shortBoxes),
			      static_cast<unsigned long long>(st.leanSearchBoxes), st.worstFrameNs * 1e-6);
		line += buf;
	}
	const size_t n = std::min(latencyCount_, latencies_.size());
	if (n) {
		std::vector<double> v(latencies_.begin(), latencies_.begin() + n);
		std::sort(v.begin(), v.end());
		std::snprintf(buf, sizeof(buf), "; latency p50 %.1f ms p99 %.1f ms", v[n / 2],
			      v[std::min(n - 1, static_cast<size_t>(std::ceil(0.99 * n)) - 1)]);
		line += buf;
	}
	// The frame path's fixed memory: how much of each arena the largest box
	// so far needed (flat once every kind of box has been seen).
	std::snprintf(buf, sizeof(buf), "; arena high-water %zu of %zu bytes", estimator.arenaUsed(),
		      estimator.arenaCapacity());
	line += buf;
	if (tracker) {
		std::snprintf(buf, sizeof(buf), " (tracker %zu of %zu)", tracker->arenaUsed(), tracker->arenaCapacity());
		line += buf;
	}
}

} // namespace ihf::app
