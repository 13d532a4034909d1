// SPDX-License-Identifier: MIT
#pragma once

// Depth from OpenNI2 (libOpenNI2): a device (by URI, or the first one found)
// or a .oni file. Files are always stepped through (OpenNI2's "manual" speed:
// a frame is produced when we ask for one, none is skipped) and the stream
// ends after one pass. realTime paces that step on a PacingClock by the
// frames' device timestamps, as a .rec replays: every frame, each no earlier
// than its time (a slow reader gets them late, not fewer). OpenNI2's own
// timed playback is not used: it drops frames a busy reader misses,
// nondeterministically, and its player thread then spins at the end of the
// file, racing the stream's destruction (a crash in 19 of 300 closes under
// load, BENCHMARKS.md); stepped with repeat on, that thread waits instead.
//
// OpenNI2 reports the field of view, not a calibration: intrinsics are
// derived from it with the principal point at the image centre unless the
// caller supplies a calibration. Depth scale follows the pixel format
// (1 mm or 100 um). OpenNI2 keeps one process-wide context; each source
// takes a reference (OpenNI::initialize/shutdown are counted). OpenNI2 hands
// every open of one URI the same device: two sources on one .oni share its
// playback position.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drivers/clock.h"
#include "drivers/frame_source.h"
#include "drivers/replay_pacer.h"

namespace ihf {

struct OpenNi2SourceOptions {
	bool realTime = false; // files only: paced at recorded speed instead of stepping
	double speed = 1.0; // realTime only: 2 = twice as fast
	PacingClock *clock = nullptr; // realTime only; null = the host steady clock
	std::optional<CameraIntrinsics> intrinsics; // calibration overriding the FOV model
};

// Keeps OpenNI2 and its drivers loaded while it lives. OpenNI2 counts
// initialize/shutdown; at the last shutdown it cancels its threads
// (pthread_cancel) and unloads the drivers, and a thread still unwinding
// through an unloaded driver crashes the process. A program that closes and
// reopens OpenNI2 sources (ihf run's reconnects, tests) holds one of these
// around them, so only its own end unloads the drivers.
class OpenNi2Session
{
public:
	OpenNi2Session();
	~OpenNi2Session();
	OpenNi2Session(const OpenNi2Session &) = delete;
	OpenNi2Session &operator=(const OpenNi2Session &) = delete;
	bool ok() const { return ok_; }

private:
	bool ok_ = false;
};

// "URI (vendor name)" of every device OpenNI2 finds (`ihf devices`).
Expected<std::vector<std::string>> listOpenNi2Devices();

class OpenNi2Source : public FrameSource
{
public:
	// deviceUri: an OpenNI2 device URI, a .oni path, or empty for the first device.
	OpenNi2Source(std::string deviceUri, OpenNi2SourceOptions options = {}, std::string uri = {});
	~OpenNi2Source() override;

	Status open() override;
	const SourceInfo &info() const override { return info_; }
	Status start() override;
	Expected<FrameOutcome> next(Frame &frame, std::chrono::nanoseconds timeout) override;
	void stop() override;
	SourceCounters counters() const override { return counters_; }

	// Frames in a .oni file (0 for a device).
	int fileFrameCount() const { return fileFrames_; }

private:
	struct State; // OpenNI2 objects, kept out of this header
	void close();
	Expected<FrameOutcome> readFrame(std::chrono::nanoseconds timeout);

	std::string deviceUri_;
	OpenNi2SourceOptions options_;
	SteadyPacingClock steadyClock_;
	PacingClock *clock_;
	ReplayPacer pacer_;
	SourceInfo info_;
	SourceCounters counters_;
	std::unique_ptr<State> state_;
	Image<uint16_t> buffer_;
	int fileFrames_ = 0;
	int fileFramesRead_ = 0;
	std::optional<uint64_t> lastIndex_;
	// A file frame read but not yet due (realTime) waits in buffer_.
	bool pending_ = false;
	uint64_t pendingIndex_ = 0;
	int64_t pendingDeviceNs_ = 0;
	int64_t pendingHostNs_ = 0;
	bool started_ = false;
};

} // namespace ihf
