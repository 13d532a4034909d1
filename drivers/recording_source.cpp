// SPDX-License-Identifier: MIT
#include "drivers/recording_source.h"

namespace ihf {

RecordingSource::RecordingSource(std::filesystem::path file, RecordingSourceOptions options,
				 std::string uri)
	: file_(std::move(file)), options_(options),
	  pacer_(options.clock ? *options.clock : steadyClock_, options.speed)
{
	info_.uri = uri.empty() ? "recording:" + file_.string() : std::move(uri);
}

Status RecordingSource::open()
{
	if (options_.pacing == Pacing::kRealTime && !ReplayPacer::validSpeed(options_.speed))
		return makeError(Errc::kInvalidArgument, info_.uri + ": playback speed must be > 0");
	Expected<RecordingReader> reader = RecordingReader::open(file_);
	if (!reader)
		return reader.error();
	reader_.emplace(std::move(*reader));
	const recording::RecordingHeader &h = reader_->header();
	info_.sensorId = h.sensorId;
	info_.intrinsics = h.intrinsics;
	info_.depthScale = h.depthScale;
	info_.live = false;
	counters_ = {};
	position_ = 0;
	pending_ = false;
	lastIndex_.reset();
	pacer_.reset();
	started_ = false;
	return {};
}

Status RecordingSource::start()
{
	if (!reader_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": start() before open()");
	const CameraIntrinsics &k = info_.intrinsics;
	if (buffer_.width() != k.width || buffer_.height() != k.height)
		buffer_ = Image<uint16_t>(k.width, k.height);
	pacer_.reset();
	started_ = true;
	return {};
}

void RecordingSource::stop()
{
	started_ = false;
	pacer_.reset();
}

Status RecordingSource::seek(uint64_t frameIndex)
{
	if (!reader_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": seek() before open()");
	std::optional<size_t> pos = reader_->find(frameIndex);
	if (!pos)
		return makeError(Errc::kNotFound, info_.uri + ": no frame with index " +
							  std::to_string(frameIndex));
	position_ = *pos;
	pending_ = false;
	pacer_.reset(); // pacing restarts at the new frame
	lastIndex_.reset();
	return {};
}

Expected<FrameOutcome> RecordingSource::next(Frame &frame, std::chrono::nanoseconds timeout)
{
	if (!started_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": next() before start()");

	for (; position_ < reader_->frameCount(); ++position_) {
		// A frame read earlier but not yet due stays in buffer_.
		if (!pending_) {
			Expected<FrameCheck> check = reader_->read(position_, pendingRecord_, buffer_.view());
			if (!check)
				return check.error();
			if (*check == FrameCheck::kCorrupt) {
				++counters_.corrupt;
				continue;
			}
			pending_ = true;
		}
		const recording::FrameRecord &rec = pendingRecord_;
		if (options_.pacing == Pacing::kRealTime && !pacer_.waitFor(rec.hostTimestampNs, timeout)) {
			++counters_.timeouts;
			return FrameOutcome::kTimeout;
		}
		pending_ = false;
		frame.index = rec.index;
		frame.deviceTimestampNs = rec.deviceTimestampNs;
		frame.hostTimestampNs = rec.hostTimestampNs;
		// Gaps in the recorded index are frames the recorder never got.
		if (lastIndex_ && frame.index > *lastIndex_ + 1)
			counters_.dropped += frame.index - *lastIndex_ - 1;
		lastIndex_ = frame.index;
		frame.intrinsics = info_.intrinsics;
		frame.depthScale = info_.depthScale;
		frame.depth = buffer_.view();
		++position_;
		++counters_.delivered;
		return FrameOutcome::kFrame;
	}
	return FrameOutcome::kEndOfStream;
}

} // namespace ihf
