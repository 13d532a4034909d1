// SPDX-License-Identifier: MIT
#pragma once

// Rasterises a SceneLayout with the DepthRenderer: the whole scene from the
// camera or from the projector (with a label per object), one object into a
// crop, and an object's full silhouette, including the part that falls
// outside the image (BOP's px_count_all and bbox_obj count it).

#include <array>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/render/depth_renderer.h"
#include "core/synth/scene_layout.h"

namespace ihf {

// Label value of objects[i] in the label buffer: i + 1 (0 = nothing).
inline uint16_t sceneLabel(size_t index) { return static_cast<uint16_t>(index + 1); }

struct ObjectSilhouette {
	// Window in image coordinates that holds the whole silhouette; it may
	// reach beyond the image.
	int x0 = 0, y0 = 0, width = 0, height = 0;
	std::vector<float> depth; // window buffer (mm), 0 off the object
	int pxCountAll = 0;
	// x, y, w, h of the covered pixels; w = xmax - xmin as bop_toolkit's
	// calc_2d_bbox (a one-pixel silhouette has w = 0).
	std::array<int, 4> bbox{-1, -1, -1, -1};

	float at(int x, int y) const // image coordinates, 0 outside the window
	{
		x -= x0;
		y -= y0;
		if (x < 0 || y < 0 || x >= width || y >= height)
			return 0.0f;
		return depth[static_cast<size_t>(y) * width + x];
	}
};

class SceneRenderer
{
public:
	SceneRenderer(const CameraIntrinsics &K, size_t maxVertices);

	const CameraIntrinsics &intrinsics() const { return K_; }

	// Clears depth/label, then draws every object seen from worldToView.
	Status renderScene(const SceneLayout &layout, const Pose &worldToView,
			   ImageView<float> depth, ImageView<uint16_t> label,
			   RenderWindow window = {});

	// Draws one object (depth-tested against what the buffers hold).
	Status renderObject(const SceneObject &obj, const Pose &worldToView, ImageView<float> depth,
			    ImageView<uint16_t> label = {}, uint16_t value = 0,
			    RenderWindow window = {});

	// The object alone, seen from the camera, over its whole silhouette.
	Expected<ObjectSilhouette> silhouette(const SceneObject &obj, const Pose &worldToCamera);

	// The view from the sensor's projector, offset by baseline along the
	// camera's +x axis with the camera's orientation.
	static Pose projectorView(const Pose &worldToCamera, double baseline);

private:
	DepthRenderer renderer_;
	CameraIntrinsics K_;
};

} // namespace ihf
