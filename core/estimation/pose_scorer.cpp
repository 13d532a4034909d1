// SPDX-License-Identifier: MIT
#include "core/estimation/pose_scorer.h"

namespace ihf {

bool renderModel(DepthRenderer &renderer, ImageView<float> render, const ObjectModel &model, const Pose &pose,
		 const CameraIntrinsics &K)
{
	render.fill(0.0f);
	return static_cast<bool>(renderer.render(model.renderMesh(), pose, K, render));
}

HypothesisScore scoreInWindow(const ScoreWindow &window, DepthRenderer &renderer, ImageView<float> render,
			      const ObjectModel &model, const Pose &pose)
{
	if (!renderModel(renderer, render, model, pose, window.K))
		return {};
	const ScoreConfig &config = *window.config;
	HypothesisScore s = scoreHypothesis(window.observed, render, config, window.downsample);
	s.boxFactor = boxAgreement(model.renderMesh(), pose, window.K, config,
				   occludedSides(window.observed, render, config, window.open));
	s.score = s.depthScore * s.boxFactor * s.edgeFactor;
	return s;
}

} // namespace ihf
