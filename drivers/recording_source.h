// SPDX-License-Identifier: MIT
#pragma once

// A .rec recording played as a frame source. Step mode hands out the frames
// in file order as fast as next() is called (deterministic: tests and
// offline runs). Real-time mode paces them by their recorded host
// timestamps (scaled by speed) on an injected PacingClock; a frame not due within
// the timeout gives kTimeout and stays pending. Frames failing their CRC are
// skipped and counted (counters().corrupt); a truncated file ends the stream
// after its last complete frame. Frames keep their recorded index and
// timestamps.

#include <filesystem>
#include <memory>
#include <optional>

#include "drivers/clock.h"
#include "drivers/frame_source.h"
#include "drivers/recording_reader.h"
#include "drivers/replay_pacer.h"

namespace ihf {

enum class Pacing {
	kStep,
	kRealTime,
};

struct RecordingSourceOptions {
	Pacing pacing = Pacing::kStep;
	double speed = 1.0; // real-time only: 2 = twice as fast
	PacingClock *clock = nullptr; // real-time only; null = the host steady clock
};

class RecordingSource : public FrameSource
{
public:
	RecordingSource(std::filesystem::path file, RecordingSourceOptions options = {},
			std::string uri = {});

	Status open() override;
	const SourceInfo &info() const override { return info_; }
	Status start() override;
	Expected<FrameOutcome> next(Frame &frame, std::chrono::nanoseconds timeout) override;
	void stop() override;
	SourceCounters counters() const override { return counters_; }

	// The next next() returns the frame with this recorded index (it must
	// exist; a corrupt one is skipped as usual). Valid after open().
	Status seek(uint64_t frameIndex);
	// Records in the file and what open() noted about its index.
	const RecordingReader *reader() const { return reader_ ? &*reader_ : nullptr; }

private:
	std::filesystem::path file_;
	RecordingSourceOptions options_;
	SteadyPacingClock steadyClock_;
	ReplayPacer pacer_;
	SourceInfo info_;
	std::optional<RecordingReader> reader_;
	Image<uint16_t> buffer_;
	SourceCounters counters_;
	size_t position_ = 0;
	bool pending_ = false; // buffer_ holds the frame at position_
	recording::FrameRecord pendingRecord_;
	bool started_ = false;
	std::optional<uint64_t> lastIndex_;
};

} // namespace ihf
