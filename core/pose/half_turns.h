// SPDX-License-Identifier: MIT
#pragma once

// Half-turn proposals: a found pose turned by 180 deg about axes through the
// model's centre. Many objects look alike from a view and its half-turn
// (the can upside down, the duck facing away), and a wrong pose of that kind
// sits at a strong vote mode with its best rotation neighbours all wrong; a
// half-turn of the best hypothesis is where the right one lies (syn200: 17
// of the can's 48 failures were within 15 deg of one of 64 half-turns of the
// winning pose). The axes are spread evenly over a
// hemisphere of the model frame (a turn about -a is the turn about a),
// generated on demand. The estimator then moves each turn so that the
// surface it shows sits where the hypothesis' did (`align`).

#include <Eigen/Core>

#include "core/geometry/pose.h"

namespace ihf {

// Bounds of HalfTurnConfig: turns polished per candidate, turns screened.
inline constexpr int kMaxHalfTurnKeep = 4;
inline constexpr int kMaxHalfTurnScreen = 32;

struct HalfTurnConfig {
	int candidates = 2; // distinct best polished hypotheses turned; 0: off
	int axes = 64;      // half-turn axes over the hemisphere
	int keep = 2;       // best-scoring turns per candidate that get an ICP polish (<= kMaxHalfTurnKeep)
	bool align = true;  // move each turn so the surface it shows sits where the candidate's did
	// Screen the turns before rendering any: each is placed (`align`) and
	// scored on the view template nearest it (view_search.h,
	// sparsePoseScore), and only the `screen` best are rendered and scored
	// in full; a render of every turn was most of a half-turn search's
	// time. 0: every turn rendered (placed by the centroid of its render),
	// as also without templates. At most
	// kMaxHalfTurnScreen.
	int screen = 8;
	// Also turn about the model frame's own three axes, the axes of its
	// box, exactly: the lattice's axis nearest the can's vertical lies 7 deg
	// off it, and a turn about it lands up to 14 deg from the can turned
	// round, too far for the polish.
	bool boxAxes = true;
};

// On when there are hypotheses to turn and axes to turn them about: the
// lattice's, or the box's alone (axes = 0 with boxAxes).
inline bool halfTurnsEnabled(const HalfTurnConfig &c) { return c.candidates > 0 && (c.axes > 0 || c.boxAxes); }

// Rotation (model frame) by 180 deg about axis i of count, 0 <= i < count.
Eigen::Matrix3d halfTurn(int i, int count);

// The turns a configuration tries: its lattice's `axes`, then the model's x,
// y and z axes when boxAxes is set; halfTurnOf(c, i) is turn i of those.
int halfTurnCount(const HalfTurnConfig &c);
Eigen::Matrix3d halfTurnOf(const HalfTurnConfig &c, int i);

// `pose` (model -> camera) turned by `turn` (model frame) about the model
// point `centre`, which stays where it was in the camera frame.
Pose turnedAbout(const Pose &pose, const Eigen::Matrix3d &turn, const Eigen::Vector3d &centre);

} // namespace ihf
