// SPDX-License-Identifier: MIT
#include "core/tracking/stream_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/estimation/rival_poses.h"
#include "core/geometry/projected_extent.h"

namespace ihf {

namespace {

// Boxes this close (IoU) on the same object are one box given twice.
constexpr double kDuplicateIou = 0.7;

double iou(const PixelBox &a, double x0, double y0, double x1, double y1)
{
	const double ix = std::max(0.0, std::min<double>(a.x + a.w, x1) - std::max<double>(a.x, x0));
	const double iy = std::max(0.0, std::min<double>(a.y + a.h, y1) - std::max<double>(a.y, y0));
	const double inter = ix * iy;
	const double uni = static_cast<double>(a.w) * a.h + (x1 - x0) * (y1 - y0) - inter;
	return uni > 0 ? inter / uni : 0.0;
}

double iou(const PixelBox &a, const PixelBox &b)
{
	return iou(a, b.x, b.y, static_cast<double>(b.x) + b.w, static_cast<double>(b.y) + b.h);
}

// delta applied `times` times (a rotation's angle scaled, its translation
// following the same screw only to first order: a frame's motion is small).
Pose repeated(const Pose &delta, double times)
{
	if (times == 1.0)
		return delta;
	Eigen::AngleAxisd aa(delta.R);
	Pose out;
	out.R = Eigen::AngleAxisd(aa.angle() * times, aa.axis()).toRotationMatrix();
	out.t = delta.t * times;
	return out;
}

// order[0, n) sorted by key, largest first, ties in their order: an
// insertion sort, stable and without the buffer std::stable_sort allocates.
template<typename Key>
void sortLargestFirst(std::span<int> order, size_t n, Key key)
{
	for (size_t k = 1; k < n; ++k)
		for (size_t j = k; j > 0 && key(order[j - 1]) < key(order[j]); --j)
			std::swap(order[j - 1], order[j]);
}

void count(StageCounter &c, int64_t ns)
{
	++c.calls;
	c.totalNs += ns;
	c.maxNs = std::max(c.maxNs, ns);
}

} // namespace

const char *boxModeName(BoxMode mode)
{
	switch (mode) {
	case BoxMode::kTrack:
		return "track";
	case BoxMode::kDetect:
		return "detect";
	case BoxMode::kDeferred:
		return "deferred";
	case BoxMode::kDuplicate:
		return "duplicate";
	case BoxMode::kSkipped:
		return "skipped";
	}
	return "?";
}

StreamEstimator::StreamEstimator(PoseEstimator &detector, const TrackerConfig &config, const Clock *clock)
	: detector_(detector), config_(config), clock_(clock ? *clock : steadyClock_), frame_(&clock_)
{
	const int window = std::max(1, config_.windowPixels > 0 ? config_.windowPixels
							      : detector.limits().maxWindowPixels);
	config_.windowPixels = window;
	const size_t vertices = detector.limits().maxMeshVertices;
	auto arena = Arena::create(TrackRefiner::arenaBytes(window, vertices));
	if (!arena)
		return;
	arena_ = std::move(*arena);
	valid_ = refiner_.reserve(window, vertices, arena_).ok();
}

void StreamEstimator::reset()
{
	for (Track &t : tracks_)
		t = Track{};
	nextId_ = 1;
}

TrackingStats StreamEstimator::stats() const
{
	TrackingStats s = stats_;
	s.frameOverruns = frame_.frame().frameOverruns();
	s.worstFrameNs = frame_.frame().worstFrameNs();
	return s;
}

int StreamEstimator::activeTracks() const
{
	return static_cast<int>(
		std::count_if(tracks_.begin(), tracks_.end(), [](const Track &t) { return t.state != TrackState::kFree; }));
}

Track *StreamEstimator::trackById(int id)
{
	for (Track &t : tracks_)
		if (t.state != TrackState::kFree && t.id == id)
			return &t;
	return nullptr;
}

Track *StreamEstimator::newTrack(const StreamBox &box, uint64_t frame)
{
	for (Track &t : tracks_) {
		if (t.state != TrackState::kFree)
			continue;
		t = Track{};
		t.state = TrackState::kPending;
		if (box.trackId > 0 && !trackById(box.trackId)) {
			t.id = box.trackId;
		} else {
			// Our own ids skip any a detector's track holds. A detector's
			// id that a track already holds (another object's, or given
			// to two boxes) is not taken twice: the box gets its own.
			while (trackById(nextId_))
				++nextId_;
			t.id = nextId_++;
		}
		t.objId = box.objId;
		t.model = box.model;
		t.lastBox = box.box;
		t.lastFrame = frame;
		++stats_.started;
		return &t;
	}
	return nullptr;
}

Pose StreamEstimator::predicted(const Track &t, uint64_t frame) const
{
	const double gap = frame > t.lastFrame ? static_cast<double>(frame - t.lastFrame) : 1.0;
	return repeated(t.velocity, gap) * t.pose;
}

void StreamEstimator::matchBoxes(std::span<const StreamBox> boxes, const CameraIntrinsics &K, uint64_t frame)
{
	const size_t n = boxes.size();
	for (size_t i = 0; i < n; ++i) {
		trackOf_[i] = nullptr;
		duplicateOf_[i] = -1;
		byOverlap_[i] = boxes[i].trackId <= 0;
	}
	// The detector's own track ids first. An id held by another object's
	// track, or claimed by an earlier box of the frame, is not the box's:
	// it is matched by overlap instead.
	for (size_t i = 0; i < n; ++i) {
		const StreamBox &b = boxes[i];
		if (!b.model || b.trackId <= 0)
			continue;
		Track *t = trackById(b.trackId);
		if (t && t->objId == b.objId && !t->matched) {
			trackOf_[i] = t;
			t->matched = true;
		} else if (t) {
			byOverlap_[i] = true;
		}
	}
	// Then by the overlap of each box with each track's predicted
	// silhouette (the last box of a track that waits for a detection),
	// greedily, the largest overlap first. Each track's region once.
	for (size_t k = 0; k < tracks_.size() && n > 0; ++k) {
		const Track &t = tracks_[k];
		Region &r = regions_[k];
		if (t.state == TrackState::kTracked) {
			const std::optional<ProjectedExtent> e = projectedExtent(t.model->mesh(), predicted(t, frame), K);
			r.valid = e.has_value();
			if (e) {
				r.box[0] = e->u0;
				r.box[1] = e->v0;
				r.box[2] = e->u1;
				r.box[3] = e->v1;
			}
		} else {
			r.valid = t.state == TrackState::kPending;
			r.box[0] = t.lastBox.x;
			r.box[1] = t.lastBox.y;
			r.box[2] = static_cast<double>(t.lastBox.x) + t.lastBox.w;
			r.box[3] = static_cast<double>(t.lastBox.y) + t.lastBox.h;
		}
	}
	size_t pairs = 0;
	for (size_t i = 0; i < n; ++i) {
		if (!boxes[i].model || trackOf_[i] || !byOverlap_[i])
			continue;
		for (size_t k = 0; k < tracks_.size(); ++k) {
			const Track &t = tracks_[k];
			if (t.state == TrackState::kFree || t.matched || t.objId != boxes[i].objId)
				continue;
			const Region &r = regions_[k];
			const double overlap = r.valid ? iou(boxes[i].box, r.box[0], r.box[1], r.box[2], r.box[3]) : 0.0;
			if (overlap >= config_.matchIou)
				pairs_[pairs++] = {static_cast<float>(overlap), static_cast<int>(i), static_cast<int>(k)};
		}
	}
	std::sort(pairs_.begin(), pairs_.begin() + static_cast<std::ptrdiff_t>(pairs),
		  [](const Pair &a, const Pair &b) {
			  return a.iou != b.iou ? a.iou > b.iou : (a.box != b.box ? a.box < b.box : a.track < b.track);
		  });
	for (size_t p = 0; p < pairs; ++p) {
		const size_t i = static_cast<size_t>(pairs_[p].box);
		Track &t = tracks_[static_cast<size_t>(pairs_[p].track)];
		if (trackOf_[i] || t.matched)
			continue;
		trackOf_[i] = &t;
		t.matched = true;
	}
	// A box left over that repeats a box of the same object is answered
	// as that box; any other starts a track.
	for (size_t i = 0; i < n; ++i) {
		if (!boxes[i].model || trackOf_[i])
			continue;
		for (size_t j = 0; j < n; ++j)
			if (j != i && boxes[j].model && boxes[j].objId == boxes[i].objId &&
			    (trackOf_[j] || j < i) && duplicateOf_[j] < 0 &&
			    iou(boxes[i].box, boxes[j].box) >= kDuplicateIou) {
				duplicateOf_[i] = static_cast<int>(j);
				break;
			}
		if (duplicateOf_[i] >= 0)
			continue;
		trackOf_[i] = newTrack(boxes[i], frame);
		if (trackOf_[i])
			trackOf_[i]->matched = true;
	}
	for (size_t i = 0; i < n; ++i)
		if (Track *t = trackOf_[i]) {
			t->lastBox = boxes[i].box;
			t->missed = 0;
		}
}

void StreamEstimator::place(Track &t, const PoseEstimate &e, uint64_t frame, bool fromTrack)
{
	if (fromTrack) {
		const double gap = frame > t.lastFrame ? static_cast<double>(frame - t.lastFrame) : 1.0;
		t.velocity = repeated(poseDelta(t.pose, e.pose), 1.0 / gap);
	} else {
		t.velocity = Pose{};
		t.detectionScore = e.score.score;
		t.detectionMargin = e.margin;
		t.confidence = e.confidence;
		t.ambiguous = e.ambiguous;
		t.ambiguityAxis = e.ambiguous ? Eigen::Vector3d(e.pose.R.transpose() * e.ambiguityAxis) : Eigen::Vector3d::Zero();
		t.detectedOnce = true;
		t.detectedFrame = frame;
	}
	t.pose = e.pose;
	t.lastFrame = frame;
	t.state = TrackState::kTracked;
	t.waiting = 0;
}

// A tracked pose is as ambiguous as the detection it follows, about the
// same axis of the object, and its confidence says so as the detection's did.
void StreamEstimator::carryAmbiguity(const Track &t, const EstimatorConfig &config, PoseEstimate &e)
{
	if (!t.ambiguous)
		return;
	e.ambiguous = true;
	e.ambiguityAxis = (e.pose.R * t.ambiguityAxis).normalized();
	e.confidence *= config.symmetryTurns.ambiguousConfidence;
}

// A refresh's detection told apart the turns the track's detection could
// not, and agrees with the tracked pose: the track is no longer ambiguous,
// and its pose, still the tracked one, has the confidence of a tracked pose
// told apart.
void StreamEstimator::settle(Track &t, const PoseEstimate &e, uint64_t frame, const EstimatorConfig &config,
			     PoseEstimate &tracked)
{
	t.ambiguous = false;
	t.ambiguityAxis = Eigen::Vector3d::Zero();
	t.confidence = e.confidence;
	t.detectedFrame = frame;
	tracked.ambiguous = false;
	tracked.ambiguityAxis = Eigen::Vector3d::Zero();
	tracked.confidence = poseConfidence(tracked.score.score, tracked.margin, config.confidence);
}

void StreamEstimator::trackBox(size_t i, uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
			       std::span<const StreamBox> boxes, const EstimatorConfig &config,
			       std::span<StreamResult> results)
{
	Track &t = *trackOf_[i];
	StreamResult &r = results[i];
	const int64_t t0 = clock_.nowNs();
	const TrackRefinement refined = refiner_.refine(depth, K, boxes[i].box, *t.model, config, config_,
							predicted(t, frame), t.detectionScore, t.detectionMargin);
	r.startNs = t0;
	r.ns = clock_.nowNs() - t0;
	count(stats_.trackTime, r.ns);
	r.tracked = true;
	r.verdict = refined.verdict;
	r.trackId = t.id;
	if (refined.verdict == TrackVerdict::kKept) {
		r.mode = BoxMode::kTrack;
		r.estimate = refined.estimate;
		place(t, refined.estimate, frame, true);
		carryAmbiguity(t, config, r.estimate);
		++stats_.tracked;
		return;
	}
	++stats_.rejected[static_cast<size_t>(refined.verdict)];
	// Kept aside: the box's answer should its detection have to wait.
	if (refined.scored) {
		r.estimate = refined.estimate;
		carryAmbiguity(t, config, r.estimate);
	}
	hasTrackedPose_[i] = refined.scored;
	needsDetection_[i] = true;
}

void StreamEstimator::detectBoxes(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
				  std::span<const StreamBox> boxes, const EstimatorConfig &config,
				  std::span<StreamResult> results)
{
	size_t wanted = 0;
	for (size_t i = 0; i < boxes.size(); ++i)
		if (needsDetection_[i])
			order_[wanted++] = static_cast<int>(i);
	if (wanted == 0)
		return;
	// The longest wait first, then the frame's order.
	sortLargestFirst(order_, wanted, [&](int i) { return trackOf_[static_cast<size_t>(i)]->waiting; });
	const bool unlimited = frame_.unlimited();
	size_t run = wanted;
	float shareMs = 0;
	if (!unlimited) {
		size_t due = 0;
		for (size_t k = 0; k < wanted; ++k)
			due += trackOf_[static_cast<size_t>(order_[k])]->waiting >= config_.maxDeferFrames - 1;
		const double leftMs = usableMs();
		const size_t fit = leftMs > 0 && config_.detectMinMs > 0
					   ? static_cast<size_t>(leftMs / static_cast<double>(config_.detectMinMs))
					   : (leftMs > 0 ? wanted : 0);
		run = std::max(due, std::min(wanted, fit));
		stats_.forced += due > fit ? due - fit : 0;
		// A due detection gets detectMinMs even past the frame's end (an
		// overrun, counted): one cut to its registration alone would start
		// its track from a guess.
		shareMs = static_cast<float>(
			std::max({leftMs, static_cast<double>(run) * static_cast<double>(config_.detectMinMs), 1e-3}));
	}
	if (run > 0) {
		const int64_t groupStart = clock_.nowNs();
		detector_.beginFrame(static_cast<int>(run), unlimited ? 0.0f : shareMs);
		for (size_t k = 0; k < run; ++k) {
			const size_t i = static_cast<size_t>(order_[k]);
			Track &t = *trackOf_[i];
			StreamResult &r = results[i];
			const int64_t t0 = clock_.nowNs();
			r.estimate = detector_.estimate(depth, K, boxes[i].box, *t.model, config);
			r.startNs = t0;
			r.ns = clock_.nowNs() - t0;
			count(stats_.detectTime, r.ns);
			r.mode = BoxMode::kDetect;
			r.trackId = t.id;
			r.waited = t.waiting;
			stats_.maxWait = std::max(stats_.maxWait, t.waiting);
			++stats_.detected;
			stats_.redetected += t.detectedOnce;
			if (r.estimate.found) {
				place(t, r.estimate, frame, false);
			} else {
				// No pose: the box was answered; the next frame tries again.
				t.state = TrackState::kPending;
				t.waiting = 0;
			}
		}
		detector_.endFrame();
		if (!unlimited)
			observeOvershoot(groupStart, shareMs);
	}
	for (size_t k = run; k < wanted; ++k) {
		const size_t i = static_cast<size_t>(order_[k]);
		Track &t = *trackOf_[i];
		StreamResult &r = results[i];
		r.mode = BoxMode::kDeferred;
		r.trackId = t.id;
		// A tracked pose scored this frame, though not kept, is a better
		// answer than none while the detection waits; its confidence says
		// how far to trust it.
		if (hasTrackedPose_[i]) {
			r.provisional = true;
			r.estimate.found = true;
			r.estimate.reason = "tracked pose not kept, waits for a detection in a later frame";
			++stats_.provisional;
		} else {
			r.estimate = PoseEstimate{};
			r.estimate.reason = "waits for a detection in a later frame";
		}
		r.waited = t.waiting;
		t.state = TrackState::kPending;
		++t.waiting;
		++stats_.deferred;
	}
}

void StreamEstimator::refreshTracks(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
				    std::span<const StreamBox> boxes, const EstimatorConfig &config,
				    std::span<StreamResult> results)
{
	const bool unlimited = frame_.unlimited();
	if (!unlimited && !(config_.detectMinMs > 0))
		return;
	// Only when no box of the frame still waits for its detection. An
	// unbudgeted frame, which time does not limit, detects again each
	// ambiguous track: the one a detection can settle (or correct) once
	// its part comes into view, which the tracked polish alone never does.
	size_t tracked = 0;
	for (size_t i = 0; i < boxes.size(); ++i) {
		if (results[i].mode == BoxMode::kDeferred)
			return;
		if (results[i].mode == BoxMode::kTrack && (!unlimited || trackOf_[i]->ambiguous))
			order_[tracked++] = static_cast<int>(i);
	}
	const double leftMs = unlimited ? 0.0 : usableMs();
	const size_t run =
		unlimited ? tracked
			  : std::min(tracked, static_cast<size_t>(std::max(0.0, leftMs / config_.detectMinMs)));
	if (run == 0)
		return;
	// The track most in doubt first: the least confident detection, and
	// of equally confident ones the oldest. A detection made in a short
	// share of a frame is wrong more often, and a wrong start is followed
	// until a refresh replaces it.
	sortLargestFirst(order_, tracked, [&](int i) {
		const Track &t = *trackOf_[static_cast<size_t>(i)];
		return static_cast<double>(frame - t.detectedFrame + 1) * (1.0 - static_cast<double>(t.confidence));
	});
	const int64_t groupStart = clock_.nowNs();
	detector_.beginFrame(static_cast<int>(run), static_cast<float>(leftMs));
	for (size_t k = 0; k < run; ++k) {
		const size_t i = static_cast<size_t>(order_[k]);
		Track &t = *trackOf_[i];
		StreamResult &r = results[i];
		const int64_t t0 = clock_.nowNs();
		const PoseEstimate e = detector_.estimate(depth, K, boxes[i].box, *t.model, config);
		const int64_t ns = clock_.nowNs() - t0;
		count(stats_.detectTime, ns);
		++stats_.refreshed;
		// A detection that tells the turns apart, near a track whose own
		// detection could not (the part has come into view), settles it:
		// the tracked pose stands, told apart now.
		if (e.found && t.ambiguous && !e.ambiguous &&
		    withinStep(config_, e.pose, t.pose, t.model->params().diameter)) {
			++stats_.refreshSettled;
			settle(t, e, frame, config, r.estimate);
			continue;
		}
		// Otherwise a detection within rivalMargin of the tracked score is
		// a tie, and a tie keeps the track (its polish is the finer).
		if (e.found && e.score.score > r.estimate.score.score + config_.rivalMargin) {
			++stats_.refreshWins;
			r.mode = BoxMode::kDetect;
			r.estimate = e;
			r.startNs = t0;
			r.ns += ns;
			// The object is where it was tracked: its motion stands too.
			const Pose velocity = t.velocity;
			const bool near = withinStep(config_, e.pose, t.pose, t.model->params().diameter);
			place(t, e, frame, false);
			if (near)
				t.velocity = velocity;
		} else {
			// The tracked pose stands, confirmed: it counts as detected now.
			t.detectedFrame = frame;
			t.confidence = std::max(t.confidence, r.estimate.confidence);
		}
	}
	detector_.endFrame();
	if (!unlimited)
		observeOvershoot(groupStart, static_cast<float>(leftMs));
}

double StreamEstimator::usableMs() const
{
	return frame_.frameLeftMs() - overshootMs_;
}

void StreamEstimator::observeOvershoot(int64_t groupStart, float shareMs)
{
	const double overMs = static_cast<double>(clock_.nowNs() - groupStart) * 1e-6 - static_cast<double>(shareMs);
	overshootMs_ = std::max(overMs, overshootMs_);
}

void StreamEstimator::endUnmatched()
{
	for (Track &t : tracks_) {
		if (t.state == TrackState::kFree)
			continue;
		if (!t.matched && ++t.missed >= config_.maxMissedFrames) {
			t = Track{};
			++stats_.lost;
		}
		t.matched = false;
	}
}

void StreamEstimator::estimateFrame(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
				    std::span<const StreamBox> boxes, const EstimatorConfig &config, float budgetMs,
				    std::span<StreamResult> results)
{
	// The frame's deadline and its overrun count are the budget planner's,
	// as for the detector's own frames.
	frame_.beginFrame(static_cast<int>(boxes.size()), budgetMs);
	// The reserve's floor, for this frame's budget (the reserve fades
	// below it between frames).
	if (!frame_.unlimited())
		overshootMs_ = std::max(overshootMs_, reserveFloorMs(budgetMs));
	++stats_.frames;
	const size_t n = std::min(boxes.size(), static_cast<size_t>(kMaxBoxes));
	for (size_t i = 0; i < boxes.size(); ++i) {
		results[i] = StreamResult{};
		needsDetection_[i % kMaxBoxes] = false;
		hasTrackedPose_[i % kMaxBoxes] = false;
	}
	for (size_t i = n; i < boxes.size(); ++i)
		results[i].estimate.reason = "more boxes in the frame than the tracker holds";
	stats_.boxes += boxes.size();
	const std::span<const StreamBox> held = boxes.first(n);
	matchBoxes(held, K, frame);
	// Tracked boxes first: they are cheap and keep what is known.
	for (size_t i = 0; i < n; ++i) {
		if (!held[i].model) {
			results[i].estimate.reason = "no model for the object";
			continue;
		}
		if (duplicateOf_[i] >= 0)
			continue;
		if (!trackOf_[i]) {
			results[i].estimate.reason = "more tracks than the tracker holds";
			continue;
		}
		if (trackOf_[i]->state == TrackState::kTracked && config_.enabled && valid_)
			trackBox(i, frame, depth, K, held, config, results);
		else
			needsDetection_[i] = true;
	}
	detectBoxes(frame, depth, K, held, config, results);
	if (config_.refresh)
		refreshTracks(frame, depth, K, held, config, results);
	for (size_t i = 0; i < n; ++i) {
		if (duplicateOf_[i] < 0)
			continue;
		const StreamResult &first = results[static_cast<size_t>(duplicateOf_[i])];
		results[i] = first;
		results[i].mode = BoxMode::kDuplicate;
		results[i].ns = 0;
		++stats_.duplicates;
	}
	for (size_t i = 0; i < boxes.size(); ++i)
		stats_.skipped += results[i].mode == BoxMode::kSkipped;
	endUnmatched();
	const int64_t end = clock_.nowNs();
	// The frame's own overshoot too (its tracked boxes ran before its
	// detections were planned); the reserve fades a frame at a time.
	if (!frame_.unlimited())
		overshootMs_ =
			std::max(static_cast<double>(end - frame_.frame().frameDeadline()) * 1e-6, overshootMs_ * kOvershootDecay);
	frame_.endFrame(end);
}

} // namespace ihf
