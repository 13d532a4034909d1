// SPDX-License-Identifier: MIT
#include "core/estimation/warm_up_scene.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace ihf {

Expected<WarmUpScene> makeWarmUpScene(const ObjectModel &model, const CameraIntrinsics &K, int maxWindowPixels,
				      DepthRenderer &renderer)
{
	const double diameter = model.params().diameter;
	if (!(diameter > 0) || K.width <= 0 || K.height <= 0 || !(K.fx > 0) || !(K.fy > 0))
		return makeError(Errc::kInvalidArgument, "warm-up needs a model diameter and the camera's intrinsics");
	const double side = 0.8 * std::sqrt(static_cast<double>(maxWindowPixels));
	Pose pose;
	pose.R = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
	pose.t = Eigen::Vector3d(0, 0, std::max(1.5 * diameter, K.fx * diameter / side));
	WarmUpScene scene{Image<float>(K.width, K.height, 0.0f), PixelBox{}};
	auto rendered = renderer.render(model.renderMesh(), pose, K, scene.depth.view());
	if (!rendered)
		return rendered.error();
	int x0 = K.width, y0 = K.height, x1 = -1, y1 = -1;
	for (int y = 0; y < K.height; ++y)
		for (int x = 0; x < K.width; ++x) {
			float &d = scene.depth.at(x, y);
			if (d > 0) {
				x0 = std::min(x0, x);
				y0 = std::min(y0, y);
				x1 = std::max(x1, x);
				y1 = std::max(y1, y);
			} else {
				d = static_cast<float>(pose.t.z() + diameter);
			}
		}
	if (x1 < x0)
		return makeError(Errc::kInvalidArgument, "warm-up: the model is not in the camera's view");
	const int mx = (x1 - x0) / 20 + 1, my = (y1 - y0) / 20 + 1;
	scene.box = PixelBox{x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};
	return scene;
}

} // namespace ihf
