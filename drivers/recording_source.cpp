// SPDX-License-Identifier: MIT
#include "drivers/recording_source.h"

#include <algorithm>
#include <cmath>

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
	pass_ = passDelivered_ = indexOffset_ = 0;
	timeOffsetNs_ = 0;
	firstGood_.reset();
	lastGood_.reset();
	indexSpan_ = 1;
	if (reader_->frameCount() > 0) {
		uint64_t lo = reader_->entry(0).frameIndex, hi = lo;
		for (size_t i = 1; i < reader_->frameCount(); ++i) {
			lo = std::min(lo, reader_->entry(i).frameIndex);
			hi = std::max(hi, reader_->entry(i).frameIndex);
		}
		indexSpan_ = hi - lo + 1;
	}
	return {};
}

void RecordingSource::noteDelivered(const recording::FrameRecord &rec)
{
	++passDelivered_;
	if (pass_ > 0)
		return;
	if (!firstGood_)
		firstGood_ = rec;
	lastGood_ = rec;
}

bool RecordingSource::wrap()
{
	if (!options_.loop || passDelivered_ == 0)
		return false;
	if (pass_ == 0) {
		// The recorded frame interval from the first pass's good frames; a
		// single frame is taken as one of a 30 Hz stream.
		double intervalNs = 1e9 / 30;
		if (lastGood_->index > firstGood_->index)
			intervalNs = static_cast<double>(lastGood_->hostTimestampNs - firstGood_->hostTimestampNs) /
				     static_cast<double>(lastGood_->index - firstGood_->index);
		timeOffsetNs_ = std::llround(intervalNs * static_cast<double>(indexSpan_));
	}
	++pass_;
	passDelivered_ = 0;
	position_ = 0;
	indexOffset_ = pass_ * indexSpan_;
	return true;
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
	pass_ = passDelivered_ = indexOffset_ = 0;
	pacer_.reset(); // pacing restarts at the new frame
	lastIndex_.reset();
	return {};
}

Expected<FrameOutcome> RecordingSource::next(Frame &frame, std::chrono::nanoseconds timeout)
{
	if (!started_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": next() before start()");

	for (;;) {
		if (position_ >= reader_->frameCount() && !wrap())
			break;
		// A frame read earlier but not yet due stays in buffer_.
		if (!pending_) {
			Expected<FrameCheck> check = reader_->read(position_, pendingRecord_, buffer_.view());
			if (!check)
				return check.error();
			if (*check == FrameCheck::kCorrupt) {
				++counters_.corrupt;
				// Counted as corrupt, not also as a gap: its index is the
				// seek index's (CRC-checked, or found by scanning).
				const uint64_t index = reader_->entry(position_).frameIndex + indexOffset_;
				if (!lastIndex_ || index > *lastIndex_)
					lastIndex_ = index;
				++position_;
				continue;
			}
			pending_ = true;
		}
		const recording::FrameRecord &rec = pendingRecord_;
		const int64_t passTimeNs = static_cast<int64_t>(pass_) * timeOffsetNs_;
		if (options_.pacing == Pacing::kRealTime &&
		    !pacer_.waitFor(rec.hostTimestampNs + passTimeNs, timeout)) {
			++counters_.timeouts;
			return FrameOutcome::kTimeout;
		}
		pending_ = false;
		noteDelivered(rec);
		frame.index = rec.index + indexOffset_;
		frame.deviceTimestampNs = rec.deviceTimestampNs + passTimeNs;
		frame.hostTimestampNs = rec.hostTimestampNs + passTimeNs;
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
