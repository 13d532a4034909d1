// SPDX-License-Identifier: MIT
#pragma once

// Frame sources by URI:
//   recording:PATH        a .rec recording (drivers/recording_source.h)
//   openni2:              the first OpenNI2 device
//   openni2:PATH.oni      an OpenNI2 recording
//   openni2:DEVICE-URI    a given OpenNI2 device (as OpenNI2 lists it)
//   v4l2:/dev/videoN?...  a V4L2 depth node (drivers/v4l2_source.h)
//   libcamera:[ID][?...]  a libcamera raw stream (drivers/libcamera_source.h;
//                         only when built with libcamera)
// The source comes back unopened: the caller runs open() and start(), and
// may run them again to reconnect after an error.

#include <memory>
#include <optional>
#include <string>

#include "drivers/clock.h"
#include "drivers/frame_source.h"
#include "drivers/recording_source.h"

namespace ihf {

struct SourceOptions {
	Pacing pacing = Pacing::kStep; // files: step, or real time
	double speed = 1.0; // files (.rec, .oni) in real time
	PacingClock *clock = nullptr; // files in real time; null = steady clock
	std::optional<CameraIntrinsics> intrinsics; // OpenNI2: calibration to use
};

// The schemes makeFrameSource() understands, for help texts.
const char *frameSourceUriHelp();

Expected<std::unique_ptr<FrameSource>> makeFrameSource(const std::string &uri,
						       const SourceOptions &options = {});

} // namespace ihf
