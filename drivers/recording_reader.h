// SPDX-License-Identifier: MIT
#pragma once

// Random access to the frames of a .rec recording. open() validates the
// header (errors name the file and the field), then locates every frame
// record: from the trailing index when it is intact, otherwise by scanning
// the records from the header on, which is how a truncated file (a recorder
// that died) still gives all its complete frames. read() checks each frame's
// CRC; a frame that fails is reported as corrupt, not as an error, so a
// player can skip it and go on. Buffers are sized at open(); read() does not
// allocate.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "drivers/recording_format.h"

namespace ihf {

enum class FrameCheck {
	kOk,
	kCorrupt, // CRC or framing failed; the frame's pixels are not usable
};

class RecordingReader
{
public:
	static Expected<RecordingReader> open(const std::filesystem::path &file);

	RecordingReader(RecordingReader &&other) noexcept;
	RecordingReader &operator=(RecordingReader &&other) noexcept;
	RecordingReader(const RecordingReader &) = delete;
	RecordingReader &operator=(const RecordingReader &) = delete;
	~RecordingReader();

	const std::filesystem::path &file() const { return file_; }
	const recording::RecordingHeader &header() const { return header_; }
	uint64_t fileSize() const { return fileSize_; }

	// Frame records found, in file order.
	size_t frameCount() const { return entries_.size(); }
	const recording::IndexEntry &entry(size_t position) const { return entries_[position]; }
	// Position of the record with this frame index, if there is one.
	std::optional<size_t> find(uint64_t frameIndex) const;

	// True when the trailing index was used; otherwise indexNote() says why
	// not and tailBytes() how many bytes after the last complete record were
	// left unread (a truncated record).
	bool indexed() const { return indexed_; }
	const std::string &indexNote() const { return indexNote_; }
	uint64_t tailBytes() const { return tailBytes_; }

	// Reads the record at position into depth (header width x height).
	// record gets its stored fields. A frame failing its checks gives
	// kCorrupt with a static reason; Errors are for I/O failures only.
	Expected<FrameCheck> read(size_t position, recording::FrameRecord &record,
				  ImageView<uint16_t> depth, const char **reason = nullptr);

private:
	RecordingReader() = default;
	bool readAt(uint64_t offset, void *data, size_t size, int *err);
	bool loadIndex();
	Status scanRecords(uint64_t from);
	size_t maxPayload(recording::Encoding encoding) const;

	std::filesystem::path file_;
	int fd_ = -1;
	uint64_t fileSize_ = 0;
	size_t headerSize_ = 0;
	recording::RecordingHeader header_;
	std::vector<recording::IndexEntry> entries_;
	bool sorted_ = true;
	bool indexed_ = false;
	std::string indexNote_;
	uint64_t tailBytes_ = 0;
	std::vector<uint8_t> raw_; // one raw frame
	std::vector<uint8_t> packed_; // the largest zlib payload
	recording::ZlibStreamsPtr inflater_;
};

} // namespace ihf
