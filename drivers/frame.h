// SPDX-License-Identifier: MIT
#pragma once

// One depth frame as every frame source hands it out. The depth view points
// into a buffer the source owns (sized at start()); it stays valid until the
// next call to next() or stop() on that source.

#include <cstdint>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf {

struct Frame {
	uint64_t index = 0; // the sensor's frame counter; gaps mean dropped frames
	int64_t deviceTimestampNs = 0; // device clock (0 if the device has none)
	// Host steady clock when the frame arrived; files: the recording's time
	// (a .rec's recorded host time, a .oni's device time: it keeps no other).
	int64_t hostTimestampNs = 0;
	CameraIntrinsics intrinsics;
	double depthScale = 1.0; // raw depth * depthScale = millimetres
	ImageView<const uint16_t> depth; // raw depth, 0 = no measurement
};

} // namespace ihf
