// SPDX-License-Identifier: MIT
#include "core/estimation/hypothesis_score.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ihf {

HypothesisScore scoreHypothesis(ImageView<const float> observed, ImageView<const float> rendered,
				const ScoreConfig &config)
{
	HypothesisScore s;
	float lo = std::numeric_limits<float>::max(), hi = 0;
	for (int y = 0; y < rendered.height; ++y) {
		const float *r = rendered.row(y);
		const float *o = observed.row(y);
		for (int x = 0; x < rendered.width; ++x) {
			if (!(r[x] > 0))
				continue;
			s.rendered++;
			lo = std::min(lo, r[x]);
			hi = std::max(hi, r[x]);
			if (!(o[x] > 0))
				continue;
			s.compared++;
			float e = o[x] - r[x];
			if (std::abs(e) <= config.inlierMm)
				s.inliers++;
			else if (e > 0)
				s.outliers++;
			else
				s.occluded++;
		}
	}
	if (s.rendered > 0) {
		s.depthMin = lo;
		s.depthMax = hi;
	}
	float denom = s.inliers + s.outliers + config.occludedWeight * s.occluded;
	s.score = denom > 0 ? s.inliers / denom : 0.0f;
	return s;
}

} // namespace ihf
