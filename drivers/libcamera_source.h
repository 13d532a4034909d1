// SPDX-License-Identifier: MIT
#pragma once

// Raw depth / ToF streams through libcamera (Debian 12: libcamera 0.0.3):
// a camera by id (or the first one), its Raw stream role, in a pixel format
// stored as unpacked 16-bit samples (R12, R10, or 16/12/10-bit Bayer, which
// ToF sensors use for their raw depth plane), buffers from
// FrameBufferAllocator with the first plane of each mmap-ed once at start().
// next() waits for a completed request up to the timeout; the frame views
// the buffer in place (stride from the stream configuration) until the next
// next(), when the request is queued again. A buffer with FrameError or
// FrameCancelled metadata is counted as corrupt and queued again. A camera
// that disappears (libcamera's cameraRemoved) gives a kIo error naming it.
//
// Depth scale: libcamera knows no depth units; scale= in the URI gives mm
// per sample (default 1). Intrinsics: fx/fy/cx/cy in the URI, else a
// pinhole from hfov= (default 58 degrees). With no camera, open() fails
// with an error saying so (and which libcamera version looked).

#include <memory>
#include <optional>
#include <string>

#include "drivers/frame_source.h"

namespace ihf {

struct LibcameraSourceOptions {
	int width = 0; // 0: the camera's default raw size
	int height = 0;
	int buffers = 4;
	double scale = 1.0; // mm per sample
	double hfovDeg = 58.0;
	std::optional<CameraIntrinsics> intrinsics;
};

// "CAMERA-ID?width=W&height=H&buffers=N&scale=MM&hfov=DEG&fx=..&fy=..&cx=..&cy=.."
// (after "libcamera:"); an empty id takes the first camera.
struct LibcameraUri {
	std::string cameraId;
	LibcameraSourceOptions options;
};
Expected<LibcameraUri> parseLibcameraUri(const std::string &rest);

// The ids of the cameras libcamera sees (for `ihf devices`).
Expected<std::vector<std::string>> listLibcameraCameras();

class LibcameraSource : public FrameSource
{
public:
	LibcameraSource(std::string cameraId, LibcameraSourceOptions options = {}, std::string uri = {});
	~LibcameraSource() override;

	Status open() override;
	const SourceInfo &info() const override { return info_; }
	Status start() override;
	Expected<FrameOutcome> next(Frame &frame, std::chrono::nanoseconds timeout) override;
	void stop() override;
	SourceCounters counters() const override { return counters_; }

private:
	struct State; // libcamera objects, kept out of this header
	void close();

	std::string cameraId_;
	LibcameraSourceOptions options_;
	SourceInfo info_;
	SourceCounters counters_;
	std::unique_ptr<State> state_;
	std::optional<uint64_t> lastIndex_;
};

} // namespace ihf
