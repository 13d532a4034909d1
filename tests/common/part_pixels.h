// SPDX-License-Identifier: MIT
#pragma once

// Where a nearly symmetric object's small part is drawn at a pose: the
// object and its body (the object without its part,
// core/synth/household_objects.h) rendered alike; a pixel is the part's
// where the object lies more than 1 mm in front of its body, or where the
// body is not drawn at all. Tests hide the part behind an occluder there.

#include <algorithm>
#include <cstdint>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"

namespace ihf::test {

// 1 on the part's pixels, 0 elsewhere (K's image size).
inline Expected<Image<uint8_t>> partPixels(const Mesh &whole, const Mesh &body, const Pose &pose,
					   const CameraIntrinsics &K)
{
	DepthImageMm wholeDepth(K.width, K.height, 0.0f), bodyDepth(K.width, K.height, 0.0f);
	DepthRenderer renderer(std::max(whole.vertices.size(), body.vertices.size()));
	for (auto [mesh, depth] : {std::pair{&whole, &wholeDepth}, std::pair{&body, &bodyDepth}}) {
		Expected<RenderStats> drawn = renderer.render(*mesh, pose, K, depth->view());
		if (!drawn)
			return drawn.error();
	}
	Image<uint8_t> part(K.width, K.height, 0);
	for (int y = 0; y < K.height; ++y)
		for (int x = 0; x < K.width; ++x) {
			const float w = wholeDepth.at(x, y), b = bodyDepth.at(x, y);
			part.at(x, y) = w > 0 && (b <= 0 || w < b - 1.0f);
		}
	return part;
}

} // namespace ihf::test
