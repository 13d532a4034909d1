// SPDX-License-Identifier: MIT
#pragma once

// Depth from a V4L2 capture device (kernel UAPI, no libv4l): 16-bit depth
// as V4L2_PIX_FMT_Z16 (depth cameras: RealSense, Orbbec over UVC) or
// V4L2_PIX_FMT_Y16 (16-bit grey, which ToF and structured-light cameras
// also use for depth). open() = QUERYCAP, ENUM_FMT, S_FMT (and S_PARM for
// a frame rate); start() = REQBUFS + mmap + QBUF + STREAMON; next() =
// poll(timeout) + DQBUF, with EINTR retried; stop() = STREAMOFF + munmap.
//
// The frame's depth view points straight into the dequeued mmap buffer
// (stride = bytesperline); that buffer is queued back at the next next() or
// stop(). A buffer the driver flags V4L2_BUF_FLAG_ERROR (or that is shorter
// than a frame) is queued back, counted as corrupt, and the wait goes on.
// The frame index is the driver's sequence number (gaps = dropped frames).
// The host timestamp is the buffer's timestamp when the driver stamps with
// CLOCK_MONOTONIC (the steady clock), capped at the time of DQBUF (a driver
// may stamp a nominal end of frame that lies ahead), else the time of DQBUF.
//
// Depth scale policy: Z16 is millimetres unless the URI says otherwise
// (scale=); Y16 carries no unit, so it is taken as millimetres too unless
// scale= gives the device's unit (e.g. scale=0.125 for 1/8 mm). V4L2 has no
// calibration: intrinsics come from fx/fy/cx/cy in the URI, else a pinhole
// with the principal point at the centre and a horizontal field of view
// (hfov=, default 58 degrees, Kinect/Xtion-class sensors).
//
// Device removal (unplug, driver unbound) makes ioctls fail with ENODEV and
// poll report POLLERR/POLLHUP: next() returns an Errc::kIo error that names
// the device and says it was removed. The caller reconnects by stop() and
// open() + start() again, which succeed once the device node is back.

#include <optional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"

namespace ihf {

enum class V4l2DepthFormat {
	kAuto, // Z16 if the device offers it, else Y16
	kZ16,
	kY16,
};

struct V4l2SourceOptions {
	V4l2DepthFormat format = V4l2DepthFormat::kAuto;
	int width = 0; // 0: keep the device's current size
	int height = 0;
	int fps = 0; // 0: keep the device's current rate
	int buffers = 4; // mmap buffers requested
	double scale = 1.0; // mm per depth unit (Z16 and Y16)
	double hfovDeg = 58.0; // for intrinsics when none are given
	std::optional<CameraIntrinsics> intrinsics; // fx, fy, cx, cy given in the URI
};

// "/dev/video0?format=y16&width=640&height=480&fps=30&scale=1&hfov=58&buffers=4&fx=..&fy=..&cx=..&cy=.."
// (the part after "v4l2:"). Unknown keys and bad values are errors.
struct V4l2Uri {
	std::string device;
	V4l2SourceOptions options;
};
Expected<V4l2Uri> parseV4l2Uri(const std::string &rest);

// A V4L2 capture node and the depth formats it offers (`ihf devices`).
struct V4l2NodeInfo {
	std::string path;
	std::string card;
	std::string driver;
	std::string busInfo;
	bool z16 = false;
	bool y16 = false;
	std::string formats; // every capture format, as fourccs
};
// Every /dev/videoN that is a single-planar capture node.
std::vector<V4l2NodeInfo> listV4l2Nodes();

class V4l2Source : public FrameSource
{
public:
	V4l2Source(std::string device, V4l2SourceOptions options = {}, std::string uri = {});
	~V4l2Source() override;

	Status open() override;
	const SourceInfo &info() const override { return info_; }
	Status start() override;
	Expected<FrameOutcome> next(Frame &frame, std::chrono::nanoseconds timeout) override;
	void stop() override;
	SourceCounters counters() const override { return counters_; }

	// The pixel format in use ("Z16 " or "Y16 ") and the row pitch in bytes.
	const std::string &pixelFormat() const { return fourcc_; }
	int bytesPerLine() const { return bytesPerLine_; }
	// poll() calls interrupted by a signal and retried.
	uint64_t interruptedWaits() const { return eintr_; }

private:
	struct Buffer {
		void *start = nullptr;
		size_t length = 0;
	};

	Error deviceError(const char *what, int err) const;
	void closeDevice();
	void releaseBuffers();
	Status requeueHeld();

	std::string device_;
	V4l2SourceOptions options_;
	SourceInfo info_;
	SourceCounters counters_;
	int fd_ = -1;
	uint32_t pixelFormat_ = 0;
	std::string fourcc_;
	int bytesPerLine_ = 0;
	size_t frameBytes_ = 0; // minimum bytesused of a complete frame
	std::vector<Buffer> buffers_; // sized at start()
	int held_ = -1; // buffer handed out by the last next()
	bool streaming_ = false;
	bool removed_ = false;
	std::optional<uint64_t> lastIndex_;
	uint64_t eintr_ = 0;
};

} // namespace ihf
