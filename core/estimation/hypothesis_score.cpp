// SPDX-License-Identifier: MIT
#include "core/estimation/hypothesis_score.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/projected_extent.h"
#include "core/pose/depth_agreement.h"

namespace ihf {

namespace {

// A drawn pixel with a 4-neighbour inside the image that is not drawn.
bool onOutline(ImageView<const float> rendered, const float *row, int x, int y)
{
	if ((x > 0 && !(row[x - 1] > 0)) || (x + 1 < rendered.width && !(row[x + 1] > 0)))
		return true;
	if (y > 0 && !(rendered.row(y - 1)[x] > 0))
		return true;
	return y + 1 < rendered.height && !(rendered.row(y + 1)[x] > 0);
}

// The scene `offset` pixels outward of an inlier (x, y) at depth z on each
// side where the rendering ends: drops (farther by more than jumpMm) and
// continues (within jumpMm) counted into s.
void countEdges(ImageView<const float> observed, ImageView<const float> rendered, int x, int y, float z,
		int offset, float jumpMm, HypothesisScore &s)
{
	constexpr int kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
	for (int d = 0; d < 4; ++d) {
		const int xn = x + kDx[d], yn = y + kDy[d];
		if (xn < 0 || yn < 0 || xn >= rendered.width || yn >= rendered.height || rendered.row(yn)[xn] > 0)
			continue;
		const int xo = x + offset * kDx[d], yo = y + offset * kDy[d];
		if (xo < 0 || yo < 0 || xo >= observed.width || yo >= observed.height)
			continue; // outside the window: unknown
		const float beyond = observed.row(yo)[xo];
		if (!(beyond > 0))
			continue;
		if (beyond > z + jumpMm)
			s.edgeDrops++;
		else if (beyond >= z - jumpMm)
			s.edgeContinues++;
	}
}

float edgeFactorOf(const HypothesisScore &s, const ScoreConfig &config)
{
	if (!(config.edgeShare > 0))
		return 1.0f;
	const float prior = std::max(0.0f, config.edgePrior);
	const float edges = static_cast<float>(s.edgeDrops) + prior * config.edgeShare;
	const float all = static_cast<float>(s.edgeDrops + s.edgeContinues) + prior;
	if (!(all > 0))
		return 1.0f;
	return std::min(1.0f, edges / all / config.edgeShare);
}

} // namespace

HypothesisScore scoreHypothesis(ImageView<const float> observed, ImageView<const float> rendered,
				const ScoreConfig &config, int downsample)
{
	HypothesisScore s;
	const bool edges = config.edgeShare > 0;
	const int ds = std::max(1, downsample);
	const int offset = std::max(1, (config.edgeOffsetPx + ds / 2) / ds); // in the window's pixels
	float lo = std::numeric_limits<float>::max(), hi = 0;
	float fit = 0; // inliers, each weighted by its residual
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
			const float e = o[x] - r[x];
			const bool inlier = std::abs(e) <= config.inlierMm;
			// An outlier on the outline is not compared at all.
			if (!inlier && e > 0 && config.skipEdgeOutliers && onOutline(rendered, r, x, y))
				continue;
			s.compared++;
			if (inlier) {
				if (edges)
					countEdges(observed, rendered, x, y, r[x], offset, config.edgeJumpMm, s);
				s.inliers++;
				fit += inlierFit(e, config.inlierMm, config.residualWeight);
			} else if (e > 0)
				s.outliers++;
			else
				s.occluded++;
		}
	}
	if (s.rendered > 0) {
		s.depthMin = lo;
		s.depthMax = hi;
	}
	s.depthScore = depthAgreement(fit, s.inliers, s.outliers, s.occluded, config.outlierWeight,
				      config.occludedWeight);
	s.edgeFactor = edgeFactorOf(s, config);
	s.score = s.depthScore * s.edgeFactor;
	return s;
}

OpenSides occludedSides(ImageView<const float> observed, ImageView<const float> rendered,
			const ScoreConfig &config, OpenSides open)
{
	if (!(config.boxOccludedSide > 0) || rendered.width <= 0 || rendered.height <= 0)
		return open;
	const int band = std::clamp(config.boxOccludedBandPx, 1, std::min(rendered.width, rendered.height));
	// Drawn and occluded pixels of the band [x0, x1) x [y0, y1).
	auto occludedShare = [&](int x0, int x1, int y0, int y1) {
		int drawn = 0, hidden = 0;
		for (int y = y0; y < y1; ++y) {
			const float *r = rendered.row(y);
			const float *o = observed.row(y);
			for (int x = x0; x < x1; ++x) {
				if (!(r[x] > 0))
					continue;
				++drawn;
				hidden += o[x] > 0 && r[x] - o[x] > config.inlierMm;
			}
		}
		return drawn >= 4 && static_cast<float>(hidden) >= config.boxOccludedSide * static_cast<float>(drawn);
	};
	const int w = rendered.width, h = rendered.height;
	open.left = open.left || occludedShare(0, band, 0, h);
	open.right = open.right || occludedShare(w - band, w, 0, h);
	open.top = open.top || occludedShare(0, w, 0, band);
	open.bottom = open.bottom || occludedShare(0, w, h - band, h);
	return open;
}

float boxAgreement(const Mesh &mesh, const Pose &pose, const CameraIntrinsics &window,
		   const ScoreConfig &config, OpenSides open)
{
	if (config.boxWeight <= 0 || mesh.vertices.empty() || window.width <= 0 || window.height <= 0)
		return 1.0f;
	const std::optional<ProjectedExtent> extent = projectedExtent(mesh, pose, window);
	if (!extent)
		return 0.0f; // behind the camera: not a pose for this box
	const float agreement =
		boxExtentAgreement(extent->u0, extent->v0, extent->u1, extent->v1, static_cast<float>(window.width),
				   static_cast<float>(window.height), config.boxMargin, config.boxMinFill, open);
	// In double, then rounded to float: pow's last bit may differ between
	// libm variants (amd64 picks an FMA one at run time), which the rounding
	// hides, and the poses must be the same bits on every target
	// (tests/estimation/golden_pose_test.cpp).
	return static_cast<float>(
		std::pow(static_cast<double>(agreement), static_cast<double>(config.boxWeight)));
}

} // namespace ihf
