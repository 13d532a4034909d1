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

} // namespace ihf
