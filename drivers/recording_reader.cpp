// SPDX-License-Identifier: MIT
#include "drivers/recording_reader.h"

#include <algorithm>
#include <cerrno>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/common/errno_text.h"

namespace ihf {

namespace fs = std::filesystem;
using namespace recording;

RecordingReader::RecordingReader(RecordingReader &&other) noexcept
{
	*this = std::move(other);
}

RecordingReader &RecordingReader::operator=(RecordingReader &&other) noexcept
{
	if (this == &other)
		return *this;
	if (fd_ >= 0)
		::close(fd_);
	file_ = std::move(other.file_);
	fd_ = std::exchange(other.fd_, -1);
	fileSize_ = other.fileSize_;
	headerSize_ = other.headerSize_;
	header_ = std::move(other.header_);
	entries_ = std::move(other.entries_);
	sorted_ = other.sorted_;
	indexed_ = other.indexed_;
	indexNote_ = std::move(other.indexNote_);
	tailBytes_ = other.tailBytes_;
	raw_ = std::move(other.raw_);
	packed_ = std::move(other.packed_);
	inflater_ = std::move(other.inflater_);
	return *this;
}

RecordingReader::~RecordingReader()
{
	if (fd_ >= 0)
		::close(fd_);
}

bool RecordingReader::readAt(uint64_t offset, void *data, size_t size, int *err)
{
	auto *p = static_cast<uint8_t *>(data);
	size_t done = 0;
	*err = 0;
	while (done < size) {
		const ssize_t n = ::pread(fd_, p + done, size - done, static_cast<off_t>(offset + done));
		if (n < 0) {
			if (errno == EINTR)
				continue;
			*err = errno;
			return false;
		}
		if (n == 0)
			return false; // end of file
		done += static_cast<size_t>(n);
	}
	return true;
}

size_t RecordingReader::maxPayload(Encoding encoding) const
{
	return encoding == Encoding::kRaw ? raw_.size() : packed_.size();
}

Expected<RecordingReader> RecordingReader::open(const fs::path &file)
{
	RecordingReader r;
	r.file_ = file;
	r.fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
	if (r.fd_ < 0) {
		const int err = errno;
		return makeError(err == ENOENT ? Errc::kNotFound : Errc::kIo,
				 file.string() + ": cannot open recording: " + errnoText(err));
	}
	struct stat st;
	if (::fstat(r.fd_, &st) != 0)
		return makeError(Errc::kIo, file.string() + ": cannot stat: " + errnoText(errno));
	if (!S_ISREG(st.st_mode))
		return makeError(Errc::kInvalidArgument, file.string() + ": not a regular file");
	r.fileSize_ = static_cast<uint64_t>(st.st_size);

	std::vector<uint8_t> head(std::min<uint64_t>(r.fileSize_, kHeaderFixedSize + kMaxSensorIdSize + 4));
	int err = 0;
	if (!head.empty() && !r.readAt(0, head.data(), head.size(), &err))
		return makeError(Errc::kIo, file.string() + ": cannot read header: " + errnoText(err));
	Expected<RecordingHeader> header = decodeHeader(head, file.string(), &r.headerSize_);
	if (!header)
		return header.error();
	r.header_ = std::move(*header);

	r.raw_.resize(rawFrameBytes(r.header_));
	r.packed_.resize(compressBound(static_cast<uLong>(r.raw_.size())));
	r.inflater_ = makeInflater();
	if (!r.inflater_)
		return makeError(Errc::kIo, file.string() + ": cannot set up zlib");

	if (!r.loadIndex()) {
		r.entries_.clear();
		if (Status s = r.scanRecords(r.headerSize_); !s)
			return s.error();
	}
	return r;
}

// Uses the footer and index if both are intact and consistent; otherwise
// leaves a note and returns false so the caller scans.
bool RecordingReader::loadIndex()
{
	const uint64_t minSize = headerSize_ + 8 + kFooterSize;
	if (fileSize_ < minSize) {
		indexNote_ = "no index (file too short for one)";
		return false;
	}
	uint8_t footer[kFooterSize];
	int err = 0;
	if (!readAt(fileSize_ - kFooterSize, footer, sizeof(footer), &err) ||
	    getU32(footer + 12) != kFooterMagic) {
		indexNote_ = "no index footer at the end of the file (truncated or unfinished recording)";
		return false;
	}
	const uint64_t indexOffset = getU64(footer);
	if (indexOffset < headerSize_ || indexOffset + 8 > fileSize_ - kFooterSize) {
		indexNote_ = "index offset in the footer is out of range";
		return false;
	}
	const uint64_t blockSize = fileSize_ - kFooterSize - indexOffset;
	std::vector<uint8_t> block(blockSize);
	if (!readAt(indexOffset, block.data(), block.size(), &err) || getU32(block.data()) != kIndexMagic) {
		indexNote_ = "index block magic is wrong";
		return false;
	}
	const uint32_t count = getU32(block.data() + 4);
	if (8 + static_cast<uint64_t>(count) * kIndexEntrySize != blockSize) {
		indexNote_ = "index entry count does not match its size";
		return false;
	}
	if (crc32Of(block) != getU32(footer + 8)) {
		indexNote_ = "index CRC mismatch";
		return false;
	}
	entries_.resize(count);
	for (uint32_t i = 0; i < count; ++i) {
		IndexEntry &e = entries_[i];
		e.frameIndex = getU64(block.data() + 8 + i * kIndexEntrySize);
		e.offset = getU64(block.data() + 16 + i * kIndexEntrySize);
		const uint64_t prevEnd = i == 0 ? headerSize_ : entries_[i - 1].offset + kFrameHeaderSize;
		if (e.offset < prevEnd || e.offset + kFrameHeaderSize > indexOffset ||
		    (i > 0 && e.frameIndex <= entries_[i - 1].frameIndex)) {
			indexNote_ = "index entry " + std::to_string(i) + " is out of order or range";
			return false;
		}
	}
	indexed_ = true;
	return true;
}

// Walks the records one by one; stops cleanly at the first record that does
// not fit in the file (truncation) or is not a frame record (the index block
// of a file whose footer is damaged, or garbage).
Status RecordingReader::scanRecords(uint64_t pos)
{
	uint8_t head[kFrameHeaderSize];
	int err = 0;
	while (pos + kFrameHeaderSize <= fileSize_) {
		if (!readAt(pos, head, sizeof(head), &err)) {
			if (err)
				return makeError(Errc::kIo, file_.string() + ": read failed at byte " +
								    std::to_string(pos) + ": " + errnoText(err));
			break;
		}
		if (getU32(head) != kFrameMagic)
			break;
		const FrameRecord rec = decodeFrameRecord(head);
		if ((rec.encoding != Encoding::kRaw && rec.encoding != Encoding::kZlib) ||
		    rec.payloadSize > maxPayload(rec.encoding))
			break;
		if (pos + kFrameHeaderSize + rec.payloadSize > fileSize_)
			break;
		if (!entries_.empty() && rec.index <= entries_.back().frameIndex)
			sorted_ = false;
		entries_.push_back({rec.index, pos});
		pos += kFrameHeaderSize + rec.payloadSize;
	}
	tailBytes_ = fileSize_ - pos;
	return {};
}

std::optional<size_t> RecordingReader::find(uint64_t frameIndex) const
{
	if (sorted_) {
		auto it = std::lower_bound(entries_.begin(), entries_.end(), frameIndex,
					   [](const IndexEntry &e, uint64_t v) { return e.frameIndex < v; });
		if (it != entries_.end() && it->frameIndex == frameIndex)
			return static_cast<size_t>(it - entries_.begin());
		return std::nullopt;
	}
	for (size_t i = 0; i < entries_.size(); ++i)
		if (entries_[i].frameIndex == frameIndex)
			return i;
	return std::nullopt;
}

Expected<FrameCheck> RecordingReader::read(size_t position, FrameRecord &record,
					   ImageView<uint16_t> depth, const char **reason)
{
	auto corrupt = [reason](const char *why) {
		if (reason)
			*reason = why;
		return FrameCheck::kCorrupt;
	};
	if (position >= entries_.size())
		return makeError(Errc::kOutOfRange, file_.string() + ": frame position " +
							    std::to_string(position) + " of " +
							    std::to_string(entries_.size()));
	const int w = header_.intrinsics.width, h = header_.intrinsics.height;
	if (depth.width != w || depth.height != h || !depth.data)
		return makeError(Errc::kInvalidArgument, file_.string() + ": output image is not " +
								 std::to_string(w) + "x" + std::to_string(h));

	const IndexEntry &e = entries_[position];
	uint8_t head[kFrameHeaderSize];
	int err = 0;
	if (!readAt(e.offset, head, sizeof(head), &err)) {
		if (err)
			return makeError(Errc::kIo, file_.string() + ": read failed: " + errnoText(err));
		return corrupt("frame record runs past the end of the file");
	}
	record = decodeFrameRecord(head);
	if (getU32(head) != kFrameMagic)
		return corrupt("frame record magic is wrong");
	if (record.encoding != Encoding::kRaw && record.encoding != Encoding::kZlib)
		return corrupt("unknown payload encoding");
	if (record.index != e.frameIndex)
		return corrupt("frame index differs from the seek index");
	if (record.encoding == Encoding::kRaw ? record.payloadSize != raw_.size()
					       : record.payloadSize > packed_.size())
		return corrupt("payload size does not fit the frame size");

	uint8_t *payload = record.encoding == Encoding::kRaw ? raw_.data() : packed_.data();
	if (!readAt(e.offset + kFrameHeaderSize, payload, record.payloadSize, &err)) {
		if (err)
			return makeError(Errc::kIo, file_.string() + ": read failed: " + errnoText(err));
		return corrupt("payload runs past the end of the file");
	}
	if (frameCrc(head, std::span<const uint8_t>(payload, record.payloadSize)) != record.crc)
		return corrupt("CRC32 mismatch");
	if (record.encoding == Encoding::kZlib) {
		if (!inflateFrame(*inflater_, std::span<const uint8_t>(packed_.data(), record.payloadSize),
				  raw_))
			return corrupt("zlib payload does not inflate to one frame");
	}

	const uint8_t *in = raw_.data();
	for (int y = 0; y < h; ++y) {
		uint16_t *row = depth.row(y);
		for (int x = 0; x < w; ++x, in += 2)
			row[x] = static_cast<uint16_t>(in[0] | (in[1] << 8));
	}
	return FrameCheck::kOk;
}

} // namespace ihf
