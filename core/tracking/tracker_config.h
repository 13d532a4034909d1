// SPDX-License-Identifier: MIT
#pragma once

// The settings of frame-to-frame tracking (stream_estimator.h). A tracked
// box is the previous frame's pose, moved on by the track's velocity and
// polished by a short projective ICP on the box's crop; it is kept when its
// score, its place in the box and its lead over the turned rivals say it
// still sits on the object, and detected afresh otherwise.

#include <cmath>

#include "core/estimation/icp_refiner.h"
#include "core/geometry/pose.h"

namespace ihf {

struct TrackerConfig {
	bool enabled = true;
	// A box belongs to a track when it overlaps the track's predicted
	// silhouette (the box of its projected model) by at least this IoU.
	float matchIou = 0.3f;
	// A track with no box for this many frames in a row ends (lost).
	int maxMissedFrames = 5;
	// A box waiting for a detection gets one within this many frames (in
	// the last one it runs whatever the time left, with detectMinMs of time
	// even past the frame's end: an overrun, counted).
	int maxDeferFrames = 3;
	// A detection runs in a budgeted frame only with at least this much of
	// the frame left for it (ms), unless it is due (maxDeferFrames).
	float detectMinMs = 10.0f;
	// Time a budgeted frame has left after its tracked boxes and the
	// detections it needs goes to detecting tracked boxes again, the track
	// most in doubt first (the least confident detection, then the oldest;
	// detectMinMs each); the detection's pose
	// replaces the tracked one when it scores higher. A track started from
	// a poor detection (a short share, the object half hidden) is then not
	// followed for long. An unbudgeted frame, which time does not limit,
	// detects again its ambiguous tracks, by the same rules: a detection
	// that tells the turns apart settles one, and the tracked polish alone
	// never would.
	bool refresh = true;
	// The tracked polish: ICP from the predicted pose on the box's crop
	// cut to the prediction's depth range.
	IcpConfig icp{8, 25.0f, 6.0f, 30, false};
	int windowPixels = 4000; // the tracked box's crop, at most (downsampled beyond)
	// A tracked pose is kept only if its score is at least minScore and at
	// least keepShare of its detection's score...
	float minScore = 0.3f;
	float keepShare = 0.75f;
	// ...its projected model agrees with the box at least this much
	// (ScoreConfig's box factor: a pose leaving its box falls)...
	float minBoxFactor = 0.5f;
	// The polish is taken only if it moved the pose from the prediction by
	// at most this share of the diameter and this many degrees and scores
	// at least as well; else the prediction itself is checked as above
	// (and below)...
	float maxStepShare = 0.3f;
	float maxStepDeg = 30.0f;
	// ...and none of its half-turns about the model's box axes scores
	// within rivalMargin of it, when its detection was won by more than
	// that (a pose the detection could not tell from its turn gains nothing
	// from being detected again). Off for symmetric models.
	bool rivals = true;
	float rivalMargin = 0.02f;
};

// Whether two poses of an object of this diameter lie within the step a
// tracked polish may take (maxStepShare, maxStepDeg).
inline bool withinStep(const TrackerConfig &c, const Pose &a, const Pose &b, double diameter)
{
	return (a.t - b.t).norm() <= c.maxStepShare * diameter &&
	       rotationAngle(a.R, b.R) <= c.maxStepDeg * M_PI / 180.0;
}

} // namespace ihf
