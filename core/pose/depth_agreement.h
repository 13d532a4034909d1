// SPDX-License-Identifier: MIT
#pragma once

// The depth-agreement rule shared by the full hypothesis score
// (core/estimation/hypothesis_score.h, on a rendering) and the view search's
// sparse score (view_search.h, on template points): a point with observed
// depth is an inlier within inlierMm of it, an outlier when the scene lies
// behind it (seen through the model) and occluded when in front. Inliers
// count by how well they fit; the score is fit / (in + wOut out + wOcc occ).
// One definition so that the search ranks rotations by the same rule that
// later decides between them.

#include <algorithm>

#include "core/geometry/open_sides.h"

namespace ihf {

// An inlier's weight: 1 - residualWeight (e / inlierMm)^2.
inline float inlierFit(float e, float inlierMm, float residualWeight)
{
	const float q = e / inlierMm;
	return 1.0f - residualWeight * (q * q);
}

// fit / (inliers + outlierWeight outliers + occludedWeight occluded), 0
// when nothing was compared.
inline float depthAgreement(float fit, int inliers, int outliers, int occluded, float outlierWeight,
			    float occludedWeight)
{
	const float denom = static_cast<float>(inliers) + outlierWeight * static_cast<float>(outliers) +
			    occludedWeight * static_cast<float>(occluded);
	return denom > 0 ? fit / denom : 0.0f;
}

// The agreement with a box of width x height pixels of a projected extent
// [u0, u1] x [v0, v1] in its pixels, before its power (ScoreConfig::
// boxWeight): the share of the extent inside the box times the box's
// covered share over minFill, at most 1. A detector's box is itself off by
// some percent: overhang within margin of the box size costs nothing, and
// none past an open side (a side the frame clipped or an occluder hides).
inline float boxExtentAgreement(float u0, float v0, float u1, float v1, float width, float height, float margin,
				float minFill, OpenSides open)
{
	const float area = std::max(1.0f, (u1 - u0) * (v1 - v0));
	const float iw = std::max(0.0f, std::min(u1, width) - std::max(u0, 0.0f));
	const float ih = std::max(0.0f, std::min(v1, height) - std::max(v0, 0.0f));
	const float mx = margin * width, my = margin * height, big = 1e30f;
	const float left = open.left ? -big : -mx, right = open.right ? big : width + mx;
	const float top = open.top ? -big : -my, bottom = open.bottom ? big : height + my;
	const float ow = std::max(0.0f, std::min(u1, right) - std::max(u0, left));
	const float oh = std::max(0.0f, std::min(v1, bottom) - std::max(v0, top));
	const float inside = std::min(1.0f, ow * oh / area);
	const float fill = iw * ih / (width * height);
	return inside * std::min(1.0f, fill / std::max(1e-3f, minFill));
}

} // namespace ihf
