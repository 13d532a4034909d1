// SPDX-License-Identifier: MIT
#pragma once

// Exact z-buffer rasterisation of a triangle mesh into caller-owned depth
// (and optional label) buffers. Depth is the camera Z in millimetres, 0 where
// nothing was drawn; a pixel is covered when its centre (integer
// coordinates, OpenCV convention) lies inside the projected triangle (top-left
// fill rule), and its depth is interpolated perspective-correctly. Drawing
// several meshes into the same buffers composes a scene: each call depth-tests
// against what is already there. No allocation per call: the renderer keeps
// scratch space sized at construction for a maximum vertex count.

#include <cstdint>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"

namespace ihf {

// Image-space window of the target buffer: the buffer's pixel (0, 0) is image
// pixel (x0, y0). Lets inference render only into a crop.
struct RenderWindow {
	int x0 = 0;
	int y0 = 0;
};

struct RenderStats {
	int trianglesDrawn = 0;
	int trianglesCulled = 0; // behind near plane, off-screen or degenerate
	int pixelsWritten = 0;
};

class DepthRenderer
{
public:
	explicit DepthRenderer(size_t maxVertices = 0);

	// Grows the scratch space (allocates); call at start-up, not per frame.
	void reserve(size_t maxVertices);
	size_t capacity() const { return capacity_; }

	// Renders mesh under pose with intrinsics K into depth (mm). If label is
	// non-empty it must match depth's size, and covered pixels get labelValue.
	// Returns kCapacity if the mesh has more vertices than reserved.
	Expected<RenderStats> render(const Mesh &mesh, const Pose &pose,
				     const CameraIntrinsics &K, ImageView<float> depth,
				     ImageView<uint16_t> label = {}, uint16_t labelValue = 0,
				     RenderWindow window = {});

	// Near plane in mm: triangles are clipped against it (a large supporting
	// plane may reach behind the camera).
	void setNearPlane(float nearMm) { near_ = nearMm; }

private:
	std::vector<Eigen::Vector3f> projected_; // (u, v, z) per vertex
	size_t capacity_ = 0;
	float near_ = 1.0f;
};

} // namespace ihf
