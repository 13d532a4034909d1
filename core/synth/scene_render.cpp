// SPDX-License-Identifier: MIT
#include "core/synth/scene_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ihf {

SceneRenderer::SceneRenderer(const CameraIntrinsics &K, size_t maxVertices)
	: renderer_(maxVertices), K_(K)
{
	renderer_.setNearPlane(1.0f);
}

Status SceneRenderer::renderObject(const SceneObject &obj, const Pose &worldToView,
				   ImageView<float> depth, ImageView<uint16_t> label,
				   uint16_t value, RenderWindow window)
{
	if (obj.mesh->vertices.size() > renderer_.capacity())
		renderer_.reserve(obj.mesh->vertices.size());
	auto stats = renderer_.render(*obj.mesh, worldToView * obj.modelToWorld, K_, depth, label,
				      value, window);
	if (!stats)
		return stats.error();
	return {};
}

Status SceneRenderer::renderScene(const SceneLayout &layout, const Pose &worldToView,
				  ImageView<float> depth, ImageView<uint16_t> label,
				  RenderWindow window)
{
	depth.fill(0.0f);
	if (!label.empty())
		label.fill(0);
	for (size_t i = 0; i < layout.objects.size(); ++i) {
		Status s = renderObject(layout.objects[i], worldToView, depth, label, sceneLabel(i),
					window);
		if (!s)
			return s;
	}
	return {};
}

Expected<ObjectSilhouette> SceneRenderer::silhouette(const SceneObject &obj,
						     const Pose &worldToCamera)
{
	const Pose pose = worldToCamera * obj.modelToWorld;
	double umin = std::numeric_limits<double>::max(), vmin = umin;
	double umax = -umin, vmax = -umin;
	for (const auto &p : obj.mesh->vertices) {
		const Eigen::Vector3d q = pose.apply(p.cast<double>());
		if (q.z() < 1.0)
			return makeError(Errc::kOutOfRange, "synth: object reaches behind the camera");
		const Eigen::Vector2d uv = K_.project(q);
		umin = std::min(umin, uv.x());
		umax = std::max(umax, uv.x());
		vmin = std::min(vmin, uv.y());
		vmax = std::max(vmax, uv.y());
	}
	// Pixel centres are at integer coordinates: covered pixels lie in
	// [floor(min), ceil(max)]. A silhouette far larger than the image is
	// cropped to 3x the image (BOP renders into such a canvas too).
	ObjectSilhouette s;
	const int W = K_.width, H = K_.height;
	const int x0 = std::max(static_cast<int>(std::floor(umin)) - 1, -W);
	const int y0 = std::max(static_cast<int>(std::floor(vmin)) - 1, -H);
	const int x1 = std::min(static_cast<int>(std::ceil(umax)) + 1, 2 * W);
	const int y1 = std::min(static_cast<int>(std::ceil(vmax)) + 1, 2 * H);
	s.x0 = x0;
	s.y0 = y0;
	s.width = std::max(0, x1 - x0 + 1);
	s.height = std::max(0, y1 - y0 + 1);
	s.depth.assign(static_cast<size_t>(s.width) * s.height, 0.0f);
	if (s.width == 0 || s.height == 0)
		return s;
	ImageView<float> view(s.depth.data(), s.width, s.height);
	Status st = renderObject(obj, worldToCamera, view, {}, 0, RenderWindow{x0, y0});
	if (!st)
		return st.error();
	int bx0 = std::numeric_limits<int>::max(), by0 = bx0, bx1 = -bx0, by1 = -bx0;
	for (int y = 0; y < s.height; ++y) {
		for (int x = 0; x < s.width; ++x) {
			if (view.at(x, y) <= 0.0f)
				continue;
			++s.pxCountAll;
			bx0 = std::min(bx0, x);
			bx1 = std::max(bx1, x);
			by0 = std::min(by0, y);
			by1 = std::max(by1, y);
		}
	}
	if (s.pxCountAll > 0)
		s.bbox = {bx0 + x0, by0 + y0, bx1 - bx0, by1 - by0};
	return s;
}

Pose SceneRenderer::projectorView(const Pose &worldToCamera, double baseline)
{
	Pose p = worldToCamera;
	p.t.x() -= baseline;
	return p;
}

} // namespace ihf
