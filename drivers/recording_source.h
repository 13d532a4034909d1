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
//
// Looped (options.loop, the URI's ?loop=1) the file is played again and
// again without end, for soak runs of a device loop on a short recording:
// each pass after the first adds the file's index span (last - first
// recorded index + 1) to the frame indices and as many recorded frame
// intervals to the timestamps, so indices and time keep increasing as a
// live sensor's do and a box feed can address every frame of every pass.
// Corrupt frames are skipped and counted on every pass. A pass without a
// single good frame ends the stream.

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
	bool loop = false; // play the file again from its start at its end
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
	// Looped: passes begun over the file (1 during the first).
	uint64_t pass() const { return pass_ + 1; }

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

	// Looping: what the next pass adds to indices and timestamps.
	bool wrap();
	void noteDelivered(const recording::FrameRecord &rec);
	uint64_t pass_ = 0;
	uint64_t passDelivered_ = 0;
	uint64_t indexSpan_ = 1; // last - first recorded index + 1
	uint64_t indexOffset_ = 0;
	int64_t timeOffsetNs_ = 0;
	// The first pass's first and last good frames: the recorded frame interval.
	std::optional<recording::FrameRecord> firstGood_, lastGood_;
};

} // namespace ihf
