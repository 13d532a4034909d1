// SPDX-License-Identifier: MIT
#pragma once

// The one interface every depth source implements (recordings, OpenNI2, and
// later V4L2, libcamera): open() acquires the device or file and learns its
// format, start() sizes every buffer and starts streaming, next() waits up to
// a timeout for one frame, stop() ends streaming (start() may follow again).
//
// next() has three normal outcomes: a frame, a timeout (nothing arrived in
// time; call again) and the end of the stream (a file played to its end).
// Errors (I/O failure, a device that disappeared) come back as Error values
// with a message naming the source; the caller decides whether to reopen
// (open() + start() again on the same object is allowed after an error).
//
// next() never allocates: the frame's depth view points into the source's
// own buffer, valid until the following next() or stop(). A V4L2 source fits
// as: open() = VIDIOC_S_FMT, start() = REQBUFS + mmap + STREAMON, next() =
// poll(timeout) + DQBUF (re-queuing the previous buffer), device removal =
// an Errc::kIo error whose message says so.

#include <chrono>
#include <cstdint>
#include <string>

#include "core/common/expected.h"
#include "drivers/frame.h"

namespace ihf {

enum class FrameOutcome {
	kFrame,
	kTimeout,
	kEndOfStream,
};

// What open() learned about the source.
struct SourceInfo {
	std::string uri; // as given to the factory, e.g. "recording:scene.rec"
	std::string sensorId; // free text: vendor, model, serial or file name
	CameraIntrinsics intrinsics; // width/height are the frame size
	double depthScale = 1.0;
	bool live = false; // a device (true) or a file that can end (false)
};

// Running counts since open(); read them at any time.
struct SourceCounters {
	uint64_t delivered = 0; // frames returned by next()
	uint64_t corrupt = 0; // frames skipped because their checksum failed
	uint64_t dropped = 0; // gaps in the frame index sequence (lost upstream)
	uint64_t timeouts = 0; // next() calls that timed out
};

class FrameSource
{
public:
	// Sources own buffers and device handles the frames point into: they
	// stay where they were made (hold them by unique_ptr to pass them on).
	FrameSource(const FrameSource &) = delete;
	FrameSource &operator=(const FrameSource &) = delete;
	virtual ~FrameSource() = default;

	virtual Status open() = 0;
	// Valid after a successful open().
	virtual const SourceInfo &info() const = 0;
	virtual Status start() = 0;
	// Fills frame when the outcome is kFrame; frame is untouched otherwise.
	virtual Expected<FrameOutcome> next(Frame &frame, std::chrono::nanoseconds timeout) = 0;
	virtual void stop() = 0;
	virtual SourceCounters counters() const = 0;

protected:
	FrameSource() = default;
};

} // namespace ihf
