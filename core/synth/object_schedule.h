// SPDX-License-Identifier: MIT
#pragma once

// Where one target object is over a sequence: resting on the table, carried
// by a hand (picked up, moved, set down elsewhere), put down from outside
// the scene or taken away. A carry lifts the object straight up, carries it
// at that height while turning it, and lowers it onto its new place, each
// phase a quintic ease (at rest at the phase ends), as a hand moves a thing
// across a table without knocking others over.

#include <vector>

#include "core/geometry/pose.h"

namespace ihf {

enum class CarryKind {
	kMove,     // from one resting place to another
	kTakeAway, // from a resting place out of the scene; absent after
	kPutDown,  // from outside the scene to a resting place; absent before
};

struct Carry {
	CarryKind kind = CarryKind::kMove;
	double start = 0, end = 0; // seconds
	Pose from, to;             // model to world at both ends
	double liftFrom = 0;       // rise above from before moving across, mm
	double liftTo = 0;         // descent onto to after moving across, mm
};

class ObjectSchedule
{
public:
	ObjectSchedule() = default;
	explicit ObjectSchedule(const Pose &rest) : initial_(rest) {}

	// Carries must come in time order without overlapping; a put-down only
	// first, a take-away only last.
	void add(const Carry &carry) { carries_.push_back(carry); }

	bool present(double t) const;
	// Model to world at t (the resting pose when not present).
	Pose modelToWorld(double t) const;
	// Present and not being carried.
	bool resting(double t) const;

	const Pose &initial() const { return initial_; }
	const std::vector<Carry> &carries() const { return carries_; }

private:
	Pose initial_;
	std::vector<Carry> carries_;
};

// The pose of a carry at phase u in [0, 1].
Pose carryPose(const Carry &carry, double u);

} // namespace ihf
