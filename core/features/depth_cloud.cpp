// SPDX-License-Identifier: MIT

#include "core/features/depth_cloud.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/geometry/fixed_order.h"

namespace ihf {

namespace {

struct Backprojector {
	ImageView<const float> depth;
	float fxInv, fyInv, cx, cy;
	float jumpMm, jumpRel;

	Eigen::Vector3f at(int u, int v, float z) const
	{
		return {(static_cast<float>(u) - cx) * z * fxInv, (static_cast<float>(v) - cy) * z * fyInv, z};
	}

	// Depth at (u, v) if it is valid and continuous with z over `steps` pixels.
	bool neighbour(int u, int v, float z, int steps, float &zn) const
	{
		if (!depth.contains(u, v))
			return false;
		zn = depth.at(u, v);
		if (!(zn > 0.0f))
			return false;
		return std::abs(zn - z) <= std::max(jumpMm, jumpRel * z) * static_cast<float>(steps);
	}

	// Tangent along (du, dv): central difference if both sides are usable,
	// else one-sided; tries the given step, then a single pixel.
	bool tangent(int u, int v, float z, int du, int dv, int step, Eigen::Vector3f &t) const
	{
		for (int s : {step, 1}) {
			float za = 0.0f, zb = 0.0f;
			const bool a = neighbour(u + du * s, v + dv * s, z, s, za);
			const bool b = neighbour(u - du * s, v - dv * s, z, s, zb);
			if (a && b) {
				t = at(u + du * s, v + dv * s, za) - at(u - du * s, v - dv * s, zb);
				return true;
			}
			if (a) {
				t = at(u + du * s, v + dv * s, za) - at(u, v, z);
				return true;
			}
			if (b) {
				t = at(u, v, z) - at(u - du * s, v - dv * s, zb);
				return true;
			}
			if (s == 1)
				break;
		}
		return false;
	}
};

} // namespace

Expected<int> cloudFromDepth(ImageView<const float> depth, const CameraIntrinsics &intrinsics,
			     PixelBox box, const DepthCloudConfig &cfg, std::span<CloudPoint> out)
{
	if (!intrinsics.valid())
		return makeError(Errc::kInvalidArgument, "cloudFromDepth: invalid intrinsics");
	if (cfg.normalStep < 1 || cfg.pixelStride < 1)
		return makeError(Errc::kInvalidArgument, "cloudFromDepth: normalStep and pixelStride must be >= 1");

	const int x0 = std::max(box.x, 0), y0 = std::max(box.y, 0);
	const int x1 = std::min(box.x + box.w, depth.width), y1 = std::min(box.y + box.h, depth.height);

	const Backprojector bp{depth,
			       static_cast<float>(1.0 / intrinsics.fx),
			       static_cast<float>(1.0 / intrinsics.fy),
			       static_cast<float>(intrinsics.cx),
			       static_cast<float>(intrinsics.cy),
			       cfg.maxJumpMm,
			       cfg.maxJumpRel};

	int count = 0;
	for (int v = y0; v < y1; v += cfg.pixelStride) {
		for (int u = x0; u < x1; u += cfg.pixelStride) {
			const float z = depth.at(u, v);
			if (!(z > 0.0f))
				continue;
			if (count == static_cast<int>(out.size()))
				return makeError(Errc::kCapacity, "cloudFromDepth: output span too small for the box");
			CloudPoint &cp = out[count++];
			cp.p = bp.at(u, v, z);
			cp.u = u;
			cp.v = v;
			cp.n.setZero();
			Eigen::Vector3f tu, tv;
			if (bp.tangent(u, v, z, 1, 0, cfg.normalStep, tu) &&
			    bp.tangent(u, v, z, 0, 1, cfg.normalStep, tv)) {
				// In a fixed order: ICP's result depends on the last
				// bits of the normals (fixed_order.h).
				Eigen::Vector3f n = crossFixedOrder(tu, tv);
				const float len = std::sqrt(dotFixedOrder(n, n));
				if (len > 0.0f) {
					n = Eigen::Vector3f(n[0] / len, n[1] / len, n[2] / len);
					// Towards the camera: the camera sits at the origin.
					cp.n = dotFixedOrder(n, cp.p) > 0.0f ? -n : n;
				}
			}
		}
	}
	return count;
}

PixelBox cloudPixelBox(std::span<const CloudPoint> cloud)
{
	if (cloud.empty())
		return {};
	int u0 = cloud[0].u, u1 = u0, v0 = cloud[0].v, v1 = v0;
	for (const CloudPoint &c : cloud) {
		u0 = std::min(u0, c.u);
		u1 = std::max(u1, c.u);
		v0 = std::min(v0, c.v);
		v1 = std::max(v1, c.v);
	}
	return {u0, v0, u1 - u0 + 1, v1 - v0 + 1};
}

} // namespace ihf
