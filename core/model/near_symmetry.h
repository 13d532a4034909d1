// SPDX-License-Identifier: MIT
#pragma once

// A near-symmetry of an object: a turn about an axis that maps most of its
// surface onto itself, all but a small part (a cup turned about its axis
// differs only by its handle, a camera turned half round by its lens). Found
// at training (core/training/near_symmetry_finder.h), stored in the forest
// file, used at inference to search the turns explicitly and to tell them
// apart on the pixels where they differ (core/estimation/symmetry_rivals.h).

#include <Eigen/Core>

namespace ihf {

struct NearSymmetry {
	Eigen::Vector3f axis = Eigen::Vector3f::UnitZ(); // unit, model frame
	Eigen::Vector3f point = Eigen::Vector3f::Zero(); // a point of the axis, mm
	// The turn in degrees; 0: every turn about the axis (a body of
	// revolution with a part on it).
	float turnDeg = 0;
	// Share of the object's pixels the turn changes in a view (the small
	// part and where it was), the mean over views all round the object
	// (core/training/turn_views.h); the largest over the turns when
	// continuous.
	float differingShare = 0;
	// Share of those views in which the turn looks alike (little of it
	// differs): where the estimator must compare the two explicitly. Known
	// at training only (-1 once read from a forest file, which does not
	// store it).
	float alikeViews = -1;
	bool continuous() const { return turnDeg == 0; }
};

} // namespace ihf
