// SPDX-License-Identifier: MIT
#pragma once

// Where `ihf run` writes its JSON lines: standard output ("stdout"), a file
// ("file:PATH", written beside PATH and renamed over it by finish(), so a
// reader never sees a half-written file), or the client connection of the
// boxes' unix socket ("socket"). Lines are formatted into a fixed buffer; a
// line is written whole. A socket client that went away loses its lines
// (counted), the run goes on.

#include <cstdint>
#include <memory>
#include <string>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"

namespace ihf::app {

class BoxFeed;

// One pose as written: {"frame","obj_id","R","t","confidence","score",
// "margin","iterations","best_iteration","icp","latency_ms","estimate_ms"},
// "ambiguous": true and "ambiguity_axis" (camera frame) when the depth
// cannot tell the pose from a turn of it about that axis (a nearly
// symmetric object whose telling part is hidden; absent otherwise),
// and with tracking "mode" ("track" or "detect") and "track_id";
// numbers in their shortest exact form. confidence = score scaled by the
// margin over the best different pose (rival_poses.h): a low confidence
// with a high score means two poses fit alike, with a low score a poor fit.
struct PoseLine {
	uint64_t frame = 0;
	int objId = 0;
	const PoseEstimate *estimate = nullptr;
	double latencyMs = 0; // frame arrival -> pose written
	double estimateMs = 0; // this box's estimation
	const char *mode = nullptr; // tracking: "track" or "detect"; null: no tracking
	int trackId = 0;
};

class PoseOutput
{
public:
	static Expected<std::unique_ptr<PoseOutput>> open(const std::string &spec, const BoxFeed *feed);
	~PoseOutput();
	PoseOutput(const PoseOutput &) = delete;
	PoseOutput &operator=(const PoseOutput &) = delete;

	Status writePose(const PoseLine &pose);
	// {"frame": F, "obj_id": O, "error": "..."}; frame or obj_id -1 are left out.
	Status writeError(int64_t frame, int64_t objId, std::string_view message);
	// The same with the box's tracking mode and track (a deferred box, a
	// tracked box without a pose).
	Status writeError(int64_t frame, int64_t objId, std::string_view message, const char *mode, int trackId);
	// Files: flush, sync and rename into place.
	Status finish();

	uint64_t linesWritten() const { return written_; }
	uint64_t linesLost() const { return lost_; }

private:
	PoseOutput() = default;
	Status writeLine(size_t size);

	std::string spec_;
	int fd_ = -1;
	bool ownsFd_ = false;
	const BoxFeed *feed_ = nullptr; // "socket": writes go to its client
	std::string path_, tmp_;
	char line_[4096];
	uint64_t written_ = 0;
	uint64_t lost_ = 0;
};

} // namespace ihf::app
