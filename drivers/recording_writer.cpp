// SPDX-License-Identifier: MIT
#include "drivers/recording_writer.h"

#include <atomic>
#include <cerrno>
#include <string>
#include <system_error>
#include <utility>

#include <unistd.h>
#include <zlib.h>

#include "core/common/errno_text.h"
#include "core/common/special_file.h"

namespace ihf {

namespace fs = std::filesystem;
using namespace recording;

Expected<RecordingWriter> RecordingWriter::create(const fs::path &file,
						  const RecordingHeader &header,
						  const RecordingWriterOptions &options)
{
	if (file.empty() || !file.has_filename())
		return makeError(Errc::kInvalidArgument, file.string() + ": not a file path");
	Expected<std::vector<uint8_t>> bytes = encodeHeader(header);
	if (!bytes)
		return makeError(bytes.error().code, file.string() + ": " + bytes.error().message);
	if (options.zlibLevel < 0 || options.zlibLevel > 9)
		return makeError(Errc::kInvalidArgument, file.string() + ": zlib level must be 0..9");

	if (isSpecialFile(file)) // its index is written last; a device would lose it
		return makeError(Errc::kInvalidArgument,
				 file.string() + ": not a regular file; a recording is written to a file");
	std::error_code ec;
	if (fs::is_directory(file, ec))
		return makeError(Errc::kInvalidArgument, file.string() + ": is a directory");
	if (!file.parent_path().empty()) {
		fs::create_directories(file.parent_path(), ec);
		if (ec)
			return makeError(Errc::kIo, file.string() + ": cannot create folder: " + ec.message());
	}

	// pid separates processes, the counter separates writers of one process.
	static std::atomic<unsigned> counter{0};
	RecordingWriter w;
	w.file_ = file;
	w.tmp_ = file;
	w.tmp_ += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
	w.stream_.reset(std::fopen(w.tmp_.c_str(), "wb"));
	if (!w.stream_) {
		const int err = errno;
		w.tmp_.clear(); // nothing to clean up
		return makeError(Errc::kIo, file.string() + ": cannot create temporary file: " +
					    errnoText(err));
	}
	w.header_ = header;
	w.options_ = options;
	w.raw_.resize(rawFrameBytes(header));
	if (options.compress) {
		w.deflater_ = makeDeflater(options.zlibLevel);
		if (!w.deflater_)
			return makeError(Errc::kIo, file.string() + ": cannot set up zlib");
		w.packed_.resize(deflatedBound(*w.deflater_, w.raw_.size()));
	}
	w.index_.reserve(options.reserveFrames);
	if (Status s = w.writeBytes(bytes->data(), bytes->size()); !s)
		return s.error();
	return w;
}

RecordingWriter::RecordingWriter(RecordingWriter &&other) noexcept
{
	*this = std::move(other);
}

// Moves spelled out: the moved-from writer must forget the temporary file,
// or its destructor would delete the file the new owner is writing.
RecordingWriter &RecordingWriter::operator=(RecordingWriter &&other) noexcept
{
	if (this == &other)
		return *this;
	abandon();
	file_ = std::move(other.file_);
	tmp_ = std::exchange(other.tmp_, {});
	stream_ = std::move(other.stream_);
	header_ = std::move(other.header_);
	options_ = other.options_;
	raw_ = std::move(other.raw_);
	packed_ = std::move(other.packed_);
	deflater_ = std::move(other.deflater_);
	index_ = std::move(other.index_);
	offset_ = other.offset_;
	finished_ = other.finished_;
	return *this;
}

RecordingWriter::~RecordingWriter()
{
	abandon();
}

void RecordingWriter::abandon()
{
	stream_.reset();
	if (!finished_ && !tmp_.empty()) {
		std::error_code ec;
		fs::remove(tmp_, ec);
	}
	tmp_.clear();
}

Status RecordingWriter::writeBytes(const void *data, size_t size)
{
	if (size && std::fwrite(data, 1, size, stream_.get()) != size)
		return makeError(Errc::kIo, file_.string() + ": write failed at byte " +
					    std::to_string(offset_) + ": " + errnoText(errno));
	offset_ += size;
	return {};
}

Status RecordingWriter::append(const FrameStamp &stamp, ImageView<const uint16_t> depth)
{
	if (!stream_ || finished_)
		return makeError(Errc::kInvalidArgument, file_.string() + ": writer is finished");
	const int w = header_.intrinsics.width, h = header_.intrinsics.height;
	if (depth.width != w || depth.height != h)
		return makeError(Errc::kInvalidArgument,
				 file_.string() + ": frame " + std::to_string(stamp.index) + " is " +
					 std::to_string(depth.width) + "x" + std::to_string(depth.height) +
					 ", the recording is " + std::to_string(w) + "x" + std::to_string(h));
	if (!index_.empty() && stamp.index <= index_.back().frameIndex)
		return makeError(Errc::kInvalidArgument,
				 file_.string() + ": frame index " + std::to_string(stamp.index) +
					 " does not follow " + std::to_string(index_.back().frameIndex));

	uint8_t *out = raw_.data();
	for (int y = 0; y < h; ++y) {
		const uint16_t *row = depth.row(y);
		for (int x = 0; x < w; ++x) {
			*out++ = static_cast<uint8_t>(row[x]);
			*out++ = static_cast<uint8_t>(row[x] >> 8);
		}
	}

	FrameRecord rec;
	rec.index = stamp.index;
	rec.deviceTimestampNs = stamp.deviceTimestampNs;
	rec.hostTimestampNs = stamp.hostTimestampNs;
	std::span<const uint8_t> payload = raw_;
	if (options_.compress) {
		size_t packedSize = 0;
		if (!deflateFrame(*deflater_, raw_, packed_, &packedSize))
			return makeError(Errc::kIo, file_.string() + ": zlib failed on frame " +
							    std::to_string(stamp.index));
		if (packedSize < raw_.size()) {
			rec.encoding = Encoding::kZlib;
			payload = std::span<const uint8_t>(packed_.data(), packedSize);
		}
	}
	rec.payloadSize = static_cast<uint32_t>(payload.size());

	uint8_t head[kFrameHeaderSize];
	encodeFrameRecord(rec, head);
	putU32(head + kFrameCrcOffset, frameCrc(head, payload));

	const uint64_t at = offset_;
	if (Status s = writeBytes(head, sizeof(head)); !s)
		return s;
	if (Status s = writeBytes(payload.data(), payload.size()); !s)
		return s;
	index_.push_back({stamp.index, at});
	return {};
}

Status RecordingWriter::finish()
{
	if (!stream_ || finished_)
		return makeError(Errc::kInvalidArgument, file_.string() + ": writer is finished");

	std::vector<uint8_t> block(8 + index_.size() * kIndexEntrySize);
	putU32(block.data(), kIndexMagic);
	putU32(block.data() + 4, static_cast<uint32_t>(index_.size()));
	for (size_t i = 0; i < index_.size(); ++i) {
		putU64(block.data() + 8 + i * kIndexEntrySize, index_[i].frameIndex);
		putU64(block.data() + 16 + i * kIndexEntrySize, index_[i].offset);
	}
	uint8_t footer[kFooterSize];
	putU64(footer, offset_);
	putU32(footer + 8, crc32Of(block));
	putU32(footer + 12, kFooterMagic);
	if (Status s = writeBytes(block.data(), block.size()); !s)
		return s;
	if (Status s = writeBytes(footer, sizeof(footer)); !s)
		return s;

	// A recording is an experiment's record: make it durable before it
	// replaces anything.
	if (std::fflush(stream_.get()) != 0 || ::fsync(fileno(stream_.get())) != 0)
		return makeError(Errc::kIo, file_.string() + ": flush failed: " + errnoText(errno));
	if (std::fclose(stream_.release()) != 0)
		return makeError(Errc::kIo, file_.string() + ": close failed: " + errnoText(errno));
	std::error_code ec;
	fs::rename(tmp_, file_, ec);
	if (ec)
		return makeError(Errc::kIo, file_.string() + ": cannot rename temporary file into place: " +
					    ec.message());
	finished_ = true;
	return {};
}

} // namespace ihf
