// SPDX-License-Identifier: MIT
#pragma once

// One object instance followed through a stream: its pose and velocity
// while tracked, or the box waiting for a detection.

#include <cstdint>

#include <Eigen/Core>

#include "core/features/cloud_point.h"
#include "core/geometry/pose.h"

namespace ihf {

class ObjectModel;

enum class TrackState : uint8_t {
	kFree,    // slot unused
	kPending, // a box that waits for its (first or next) detection
	kTracked, // a pose to follow from frame to frame
};

struct Track {
	TrackState state = TrackState::kFree;
	int id = 0;
	int objId = 0;
	const ObjectModel *model = nullptr;
	Pose pose;                 // real camera, at lastFrame
	Pose velocity;             // pose change per frame (camera frame)
	PixelBox lastBox;          // the box it last matched
	uint64_t lastFrame = 0;    // the frame of `pose`
	int missed = 0;            // frames in a row without a box
	int waiting = 0;           // frames its box has waited for a detection
	float detectionScore = 0;  // the score and margin its pose was detected with
	float detectionMargin = 0;
	float confidence = 0;      // of its last detection, or of the tracked pose a refresh confirmed
	// Its last detection could not tell the pose from a turn of it about
	// this axis (model frame): the part that tells them apart was hidden.
	// Following the pose does not tell them apart either.
	bool ambiguous = false;
	Eigen::Vector3d ambiguityAxis = Eigen::Vector3d::Zero();
	bool detectedOnce = false; // a detection has placed it (a re-detection is counted as such)
	uint64_t detectedFrame = 0; // the frame of its last detection
	bool matched = false;      // in the current frame
};

// The pose change from `from` to `to`, applied on the left: to = delta * from.
inline Pose poseDelta(const Pose &from, const Pose &to)
{
	return to * from.inverse();
}

} // namespace ihf
