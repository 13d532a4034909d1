// SPDX-License-Identifier: MIT
#include "core/estimation/virtual_crop.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/rotation.h"

namespace ihf {

CropStatus makeVirtualCrop(ImageView<const float> depth, const CameraIntrinsics &K,
			   const PixelBox &box, std::span<float> buffer, VirtualCrop &out)
{
	if (box.w <= 0 || box.h <= 0 || buffer.empty())
		return CropStatus::kEmptyBox;
	PixelBox c;
	c.x = std::max(box.x, 0);
	c.y = std::max(box.y, 0);
	int x1 = std::min(box.x + box.w, depth.width);
	int y1 = std::min(box.y + box.h, depth.height);
	c.w = x1 - c.x;
	c.h = y1 - c.y;
	if (c.w <= 0 || c.h <= 0)
		return CropStatus::kOutsideImage;

	VirtualCrop &crop = out;
	crop = VirtualCrop();
	crop.clippedBox = c;
	const Eigen::Vector3d ray((c.x + 0.5 * (c.w - 1) - K.cx) / K.fx,
				  (c.y + 0.5 * (c.h - 1) - K.cy) / K.fy, 1.0);
	crop.rotation = rayAlignment(ray);
	const Eigen::Matrix3d Rt = crop.rotation.transpose();

	// Window of the box in the virtual image (full resolution first).
	double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
	for (int corner = 0; corner < 4; ++corner) {
		double u = (corner & 1) ? c.x + c.w - 0.5 : c.x - 0.5;
		double v = (corner & 2) ? c.y + c.h - 0.5 : c.y - 0.5;
		Eigen::Vector3d p = Rt * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
		double pu = K.fx * p.x() / p.z() + K.cx, pv = K.fy * p.y() / p.z() + K.cy;
		u0 = std::min(u0, pu);
		u1 = std::max(u1, pu);
		v0 = std::min(v0, pv);
		v1 = std::max(v1, pv);
	}
	const size_t maxPixels = buffer.size();
	int ds = 1;
	for (;; ++ds) {
		double w = std::ceil((u1 - u0) / ds), h = std::ceil((v1 - v0) / ds);
		if (w * h <= static_cast<double>(maxPixels))
			break;
	}
	crop.downsample = ds;
	const double fx = K.fx / ds, fy = K.fy / ds;
	const double cx = (K.cx + 0.5) / ds - 0.5, cy = (K.cy + 0.5) / ds - 0.5;
	const int wx0 = static_cast<int>(std::floor((u0 + 0.5) / ds));
	const int wy0 = static_cast<int>(std::floor((v0 + 0.5) / ds));
	const int ww = static_cast<int>(std::ceil((u1 + 0.5) / ds)) - wx0;
	const int wh = static_cast<int>(std::ceil((v1 + 0.5) / ds)) - wy0;
	crop.intrinsics = CameraIntrinsics{fx, fy, cx - wx0, cy - wy0, ww, wh};
	crop.depth = ImageView<float>(buffer.data(), ww, wh, ww);

	// Backward warp: each virtual pixel's ray, rotated into the real camera,
	// picks the nearest real pixel inside the box.
	const Eigen::Matrix3d &R = crop.rotation;
	int valid = 0;
	for (int y = 0; y < wh; ++y) {
		float *row = crop.depth.row(y);
		for (int x = 0; x < ww; ++x) {
			Eigen::Vector3d rv((x - crop.intrinsics.cx) / fx, (y - crop.intrinsics.cy) / fy, 1.0);
			Eigen::Vector3d rr = R * rv;
			row[x] = 0;
			if (rr.z() <= 0)
				continue;
			int u = static_cast<int>(std::lround(K.fx * rr.x() / rr.z() + K.cx));
			int v = static_cast<int>(std::lround(K.fy * rr.y() / rr.z() + K.cy));
			if (!c.contains(u, v))
				continue;
			float d = depth.at(u, v);
			if (!(d > 0))
				continue;
			Eigen::Vector3d p((u - K.cx) * d / K.fx, (v - K.cy) * d / K.fy, d);
			row[x] = static_cast<float>(Rt.row(2).dot(p));
			++valid;
		}
	}
	crop.validPixels = valid;
	return CropStatus::kOk;
}

} // namespace ihf
