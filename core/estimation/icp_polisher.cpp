// SPDX-License-Identifier: MIT
#include "core/estimation/icp_polisher.h"

#include "core/features/depth_cloud.h"

namespace ihf {

void cutToDepthRange(ImageView<const float> observed, float nearMm, float farMm, std::span<float> out)
{
	size_t i = 0;
	for (int y = 0; y < observed.height; ++y) {
		const float *row = observed.row(y);
		for (int x = 0; x < observed.width; ++x, ++i) {
			const float d = row[x];
			out[i] = (d > nearMm && d < farMm) ? d : 0.0f;
		}
	}
}

PolishResult polishFromCloud(const ScoreWindow &window, const ObjectModel &model, const Pose &start,
			     std::span<const CloudPoint> cloud, const IcpConfig &icp, DepthRenderer &renderer,
			     ImageView<float> render)
{
	PolishResult out;
	out.icp = refineIcp(cloud, model.renderMesh(), start, window.K, renderer, render, icp);
	if (out.icp.iterations > 0) {
		out.pose = out.icp.pose;
		out.score = scoreInWindow(window, renderer, render, model, out.pose);
		out.valid = true;
	}
	return out;
}

PolishResult polishInWindow(const ScoreWindow &window, const ObjectModel &model, const Pose &start, float nearMm,
			    float farMm, const IcpConfig &icp, const PolishBuffers &buffers)
{
	const int w = window.observed.width, h = window.observed.height;
	cutToDepthRange(window.observed, nearMm, farMm, buffers.mask);
	const ImageView<float> maskView(buffers.mask.data(), w, h, w);
	auto points = cloudFromDepth(maskView, window.K, PixelBox{0, 0, w, h}, model.params().cloud, buffers.cloud);
	const int n = points ? *points : 0;
	return polishFromCloud(window, model, start, buffers.cloud.first(static_cast<size_t>(n)), icp,
			       *buffers.renderer, buffers.render);
}

} // namespace ihf
