// SPDX-License-Identifier: MIT
#pragma once

// Exact z-buffer rasterisation of a triangle mesh into caller-owned depth
// (and optional label) buffers. Depth is the camera Z in millimetres, 0 where
// nothing was drawn; a pixel is covered when its centre (integer
// coordinates, OpenCV convention) lies inside the projected triangle (top-left
// fill rule, vertices snapped to 1/256 pixel), and its depth is the exact
// intersection of the pixel's ray with the triangle's plane (1/z is linear in
// the image). Back faces are drawn too (meshes may have inconsistent winding)
// unless setCullBackFaces() says the mesh is closed and wound outwards.
// Triangles crossing the near plane are clipped against it, so a large plane
// reaching behind the camera renders correctly. Drawing several meshes into
// the same buffers composes a scene: each call depth-tests against what is
// already there. No allocation per call: the renderer keeps scratch space
// sized by reserve() for a maximum vertex count, in an arena of the
// renderer's own or one shared with the rest of the frame path.

#include <cstdint>
#include <span>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/runtime/arena.h"

namespace ihf {

// Image-space window of the target buffer: the buffer's pixel (0, 0) is image
// pixel (x0, y0). Lets inference render only into a crop (the cost is mostly
// per triangle, so a crop saves pixel work only). Every pixel depends
// only on its image coordinates, so a window render equals the same region of
// a full render bit for bit. Windows must lie within
// [-kMaxWindowCoord, kMaxWindowCoord) in both axes.
struct RenderWindow {
	int x0 = 0;
	int y0 = 0;
};

struct RenderStats {
	int trianglesDrawn = 0;
	// Behind the near plane, with no pixel centre inside the window, or
	// degenerate (zero area in the image or in space).
	int trianglesCulled = 0;
	int pixelsWritten = 0; // depth-test passes, overdraw included
};

class DepthRenderer
{
public:
	static constexpr int kMaxWindowCoord = 8192;

	explicit DepthRenderer(size_t maxVertices = 0);

	// Grows the scratch space in an arena of the renderer's own
	// (allocates); call at start-up, not per frame.
	void reserve(size_t maxVertices);
	// Scratch for maxVertices carved from a shared arena that must outlive
	// the renderer (kCapacity if it is too small; capacity is then 0).
	Status reserve(size_t maxVertices, Arena &arena);
	static size_t arenaBytes(size_t maxVertices);
	size_t capacity() const { return capacity_; }

	// Renders mesh under pose with intrinsics K into depth (mm). If label is
	// non-empty it must match depth's size, and covered pixels get labelValue.
	// Returns kCapacity if the mesh has more vertices than reserved,
	// kOutOfRange for a face index past the vertex list, kInvalidArgument for
	// bad intrinsics, near plane, buffer sizes or window.
	Expected<RenderStats> render(const Mesh &mesh, const Pose &pose,
				     const CameraIntrinsics &K, ImageView<float> depth,
				     ImageView<uint16_t> label = {}, uint16_t labelValue = 0,
				     RenderWindow window = {});

	// Near plane in mm (> 0): triangles are clipped against it (a large
	// supporting plane may reach behind the camera).
	void setNearPlane(float nearMm) { near_ = nearMm; }
	float nearPlane() const { return near_; }

	// Skip triangles that face away from the camera. Only for a closed
	// mesh wound consistently outwards (isClosedOutward()) seen from
	// outside: its back faces always lie behind its front faces, so the
	// depth is the same, at about half the triangles' cost.
	void setCullBackFaces(bool cull) { cullBackFaces_ = cull; }
	bool cullBackFaces() const { return cullBackFaces_; }

private:
	// Scratch per vertex, split so the per-triangle setup touches only the
	// 8-byte snapped image position (1/256 pixel; sx is kNoScreen when the
	// vertex needs clipping, flags_ then says why).
	struct ScreenVertex {
		int32_t sx, sy;
	};

	template<typename A>
	bool carve(A &arena, size_t maxVertices);

	Arena own_; // used by reserve(maxVertices) only
	std::span<ScreenVertex> screen_;
	std::span<uint8_t> flags_;
	std::span<Eigen::Vector3f> camera_; // camera coordinates, mm
	size_t capacity_ = 0;
	float near_ = 1.0f;
	bool cullBackFaces_ = false;
};

} // namespace ihf
