// SPDX-License-Identifier: MIT
#pragma once

// Poses for a stream of frames whose boxes show the same objects frame
// after frame. Each box is matched to a track (its detector's track_id
// when given, else the overlap of the box with the track's predicted
// silhouette); a matched box is tracked: the previous pose moved on by the
// track's constant velocity and polished (track_refiner.h). A box that no
// track explains, or whose tracked pose was not kept, is detected by the
// cold estimator (PoseEstimator), which starts or restarts its track.
//
// The frame's budget is shared: tracked boxes first, then detections,
// oldest wait first, each only while at least detectMinMs is left for it;
// a detection that does not fit waits for the next frame (counted, and its
// box answered as deferred: with the tracked pose that was not kept, when
// one was scored, as an unconfirmed answer with its own confidence), and
// one that has waited maxDeferFrames runs whatever the time left. A track
// with no box for maxMissedFrames ends.
// Nothing here allocates after construction: tracks, per-frame lists and
// the refiner's buffers are fixed at start-up.

#include <array>
#include <span>

#include "core/estimation/pose_estimator.h"
#include "core/runtime/arena.h"
#include "core/runtime/clock.h"
#include "core/tracking/track.h"
#include "core/tracking/track_refiner.h"
#include "core/tracking/tracker_config.h"

namespace ihf {

struct StreamBox {
	int objId = 0;
	PixelBox box;
	int trackId = 0;                    // the detector's track, 0: none
	const ObjectModel *model = nullptr; // null: no model for objId (not estimated)
};

enum class BoxMode : uint8_t {
	kTrack,     // the tracked pose
	kDetect,    // a cold detection
	kDeferred,  // waits for a detection in a later frame (found: its tracked pose not kept, unconfirmed)
	kDuplicate, // repeats another box of the frame (same object, same place)
	kSkipped,   // no model, or more boxes than the frame holds
};

const char *boxModeName(BoxMode mode);

struct StreamResult {
	BoxMode mode = BoxMode::kSkipped;
	int trackId = 0;
	PoseEstimate estimate;             // found: a pose; else reason
	TrackVerdict verdict = TrackVerdict::kKept; // of the tracked attempt, when there was one
	bool tracked = false;              // a tracked pose was tried
	bool provisional = false;          // deferred, answered with the tracked pose that was not kept
	int waited = 0;                    // frames the box waited for this detection
	int64_t startNs = 0;               // when its estimation began (the clock's time)
	int64_t ns = 0;                    // time spent on the box
};

struct TrackingStats {
	uint64_t frames = 0;
	uint64_t boxes = 0;
	uint64_t tracked = 0;     // boxes answered by tracking
	uint64_t detected = 0;    // boxes answered by a detection
	uint64_t redetected = 0;  // of those, after a tracked pose was not kept
	uint64_t deferred = 0;    // detections moved to a later frame
	uint64_t provisional = 0; // of those, answered with their tracked pose not kept
	uint64_t forced = 0;      // detections run though the frame had no room (due)
	uint64_t refreshed = 0;   // tracked boxes detected again (budgeted: with the frame's spare time;
				  // unbudgeted: the ambiguous ones)
	uint64_t refreshWins = 0; // of those, the detection scored higher and replaced the track
	uint64_t refreshSettled = 0; // of those, ambiguous tracks the detection told apart (their pose kept)
	uint64_t duplicates = 0;
	uint64_t skipped = 0;
	uint64_t started = 0;     // tracks begun
	uint64_t lost = 0;        // tracks ended for want of boxes
	std::array<uint64_t, 9> rejected{}; // tracked poses not kept, by TrackVerdict
	StageCounter trackTime;   // tracked boxes
	StageCounter detectTime;  // detected boxes
	int maxWait = 0;          // the longest a box waited for its detection
	uint64_t frameOverruns = 0; // budgeted frames that ended past their budget (the frame budget's)
	int64_t worstFrameNs = 0;
};

class StreamEstimator
{
public:
	static constexpr int kMaxTracks = 64;
	static constexpr int kMaxBoxes = 64; // per frame

	// detector: the cold estimator, on the same clock; maxMeshVertices as
	// its limits. The refiner's arena is allocated here.
	StreamEstimator(PoseEstimator &detector, const TrackerConfig &config, const Clock *clock = nullptr);

	bool valid() const { return valid_; }
	const TrackerConfig &config() const { return config_; }

	// A new stream: every track ends (not counted as lost).
	void reset();

	// One frame's boxes into results[i] (results.size() >= boxes.size()),
	// inside budgetMs (<= 0: unlimited). frame: the frame's index, for
	// the tracks' velocity across missed frames.
	void estimateFrame(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
			   std::span<const StreamBox> boxes, const EstimatorConfig &config, float budgetMs,
			   std::span<StreamResult> results);

	TrackingStats stats() const;
	int activeTracks() const;
	size_t arenaCapacity() const { return arena_.capacity(); }
	size_t arenaUsed() const { return arena_.highWater(); }

private:
	Track *newTrack(const StreamBox &box, uint64_t frame);
	Track *trackById(int id);
	// The track a box belongs to (null: none), by id or overlap.
	void matchBoxes(std::span<const StreamBox> boxes, const CameraIntrinsics &K, uint64_t frame);
	Pose predicted(const Track &t, uint64_t frame) const;
	void trackBox(size_t i, uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
		      std::span<const StreamBox> boxes, const EstimatorConfig &config, std::span<StreamResult> results);
	void detectBoxes(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
			 std::span<const StreamBox> boxes, const EstimatorConfig &config, std::span<StreamResult> results);
	void refreshTracks(uint64_t frame, ImageView<const float> depth, const CameraIntrinsics &K,
			   std::span<const StreamBox> boxes, const EstimatorConfig &config, std::span<StreamResult> results);
	void place(Track &t, const PoseEstimate &e, uint64_t frame, bool fromTrack);
	// e, a pose that follows t, flagged ambiguous as t's detection was.
	static void carryAmbiguity(const Track &t, const EstimatorConfig &config, PoseEstimate &e);
	// t was ambiguous; a refresh's detection e, near it, told the turns apart.
	static void settle(Track &t, const PoseEstimate &e, uint64_t frame, const EstimatorConfig &config,
			   PoseEstimate &tracked);
	// The frame's time left for detections, less what detections have run
	// past their share lately.
	double usableMs() const;
	void observeOvershoot(int64_t groupStart, float shareMs);

	// A detection runs a little past its share (its registration is never
	// cut, a stage's cost is a prediction): the largest recent overshoot of
	// a detection or a frame, fading by this factor a frame, is kept off
	// later shares so that frames end inside their budget.
	static constexpr double kOvershootDecay = 0.995;
	// The reserve never falls below this share of the frame's budget: a
	// stage runs a little past its predicted cost often enough that frames
	// planned to their last millisecond end past it about one time in a
	// hundred (on seq3 and seq8 at 33 ms, a floor of 5 % halves the
	// overruns at the same accuracy: BENCHMARKS.md, streams).
	static constexpr double kReserveFloor = 0.05;
	static double reserveFloorMs(float budgetMs) { return kReserveFloor * static_cast<double>(budgetMs); }
	double overshootMs_ = 0;
	void endUnmatched();

	PoseEstimator &detector_;
	TrackerConfig config_;
	SteadyClock steadyClock_;
	const Clock &clock_;
	Arena arena_;
	TrackRefiner refiner_;
	BudgetPlanner frame_; // the whole frame's: tracked boxes and detections
	bool valid_ = false;
	int nextId_ = 1;
	std::array<Track, kMaxTracks> tracks_{};
	// Per frame: each box's track (null: none) and what it needs.
	std::array<Track *, kMaxBoxes> trackOf_{};
	std::array<bool, kMaxBoxes> needsDetection_{};
	std::array<bool, kMaxBoxes> hasTrackedPose_{}; // a tracked pose, not kept, scored (in its result)
	std::array<int, kMaxBoxes> order_{};
	std::array<int, kMaxBoxes> duplicateOf_{}; // the box a duplicate repeats, -1: none
	std::array<bool, kMaxBoxes> byOverlap_{};  // matched by overlap: no detector id, or one not its own
	struct Pair {
		float iou;
		int box;
		int track;
	};
	std::array<Pair, kMaxBoxes * kMaxTracks> pairs_{};
	// Per frame: each track's region in the image, x0, y0, x1, y1 (its
	// predicted silhouette's box, or its last box while it waits).
	struct Region {
		bool valid = false;
		double box[4] = {0, 0, 0, 0};
	};
	std::array<Region, kMaxTracks> regions_{};
	TrackingStats stats_;
};

} // namespace ihf
