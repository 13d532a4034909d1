// SPDX-License-Identifier: MIT
#include "core/geometry/projected_extent.h"

#include <algorithm>
#include <limits>

#include "core/geometry/fixed_order.h"

namespace ihf {

std::optional<ProjectedExtent> projectedExtent(const Mesh &mesh, const Pose &pose, const CameraIntrinsics &K)
{
	if (mesh.vertices.empty())
		return std::nullopt;
	const size_t stride = std::max<size_t>(1, mesh.vertices.size() / 512);
	const Eigen::Matrix3f R = pose.R.cast<float>();
	const Eigen::Vector3f t = pose.t.cast<float>();
	ProjectedExtent e;
	e.u0 = e.v0 = std::numeric_limits<float>::max();
	e.u1 = e.v1 = -e.u0;
	for (size_t i = 0; i < mesh.vertices.size(); i += stride) {
		const Eigen::Vector3f x = transformFixedOrder(R, mesh.vertices[i], t);
		if (!(x.z() > 1.0f))
			return std::nullopt;
		const float u = static_cast<float>(K.fx) * x.x() / x.z() + static_cast<float>(K.cx);
		const float v = static_cast<float>(K.fy) * x.y() / x.z() + static_cast<float>(K.cy);
		e.u0 = std::min(e.u0, u);
		e.u1 = std::max(e.u1, u);
		e.v0 = std::min(e.v0, v);
		e.v1 = std::max(e.v1, v);
	}
	return e;
}

} // namespace ihf
