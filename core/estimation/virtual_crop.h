// SPDX-License-Identifier: MIT
#pragma once

// Turns a box of the depth frame into the view of a virtual camera that
// looks straight through the box centre: a pure rotation R_v of the real
// camera, so the crop is resampled through the homography K R_v^T K^-1.
// Training views have the object on the optical axis; in the virtual camera
// a test object is near that axis too, so the forest's offsets and
// rotations (which are camera-frame quantities) transfer. Results map back
// with x_real = R_v x_virtual.
//
// Policy for large boxes: if the window would exceed maxPixels, the virtual
// camera gets a proportionally smaller focal length (an integer
// downsampling factor), so the box is processed at lower resolution rather
// than rejected.

#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "core/common/image.h"
#include "core/features/cloud_point.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf {

struct VirtualCrop {
	Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); // R_v
	CameraIntrinsics intrinsics; // of the window (pixel (0,0) = window corner)
	ImageView<float> depth;      // the resampled window, mm (0 = none)
	int downsample = 1;
	int validPixels = 0;
	PixelBox clippedBox;         // the box clipped to the frame
};

enum class CropStatus : uint8_t {
	kOk,
	kEmptyBox,     // zero width or height
	kOutsideImage, // no overlap with the frame
};

// The window is at most buffer.size() pixels (the downsampling policy
// above). On kOk, out describes the crop, its depth a view into buffer. A
// status rather than an Expected: the frame path builds no error strings.
CropStatus makeVirtualCrop(ImageView<const float> depth, const CameraIntrinsics &K,
			   const PixelBox &box, std::span<float> buffer, VirtualCrop &out);

} // namespace ihf
