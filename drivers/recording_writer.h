// SPDX-License-Identifier: MIT
#pragma once

// Writes a .rec recording frame by frame. Frames go to a temporary file
// beside the target ("F.tmp-<pid>-<n>"); finish() appends the seek index and
// renames it over the target, so a reader never sees a half-written file
// under the target name. Destroying an unfinished writer deletes the
// temporary file. Buffers (and zlib's state) are set up at create(): append()
// does not allocate, except to grow the in-memory seek index beyond
// reserveFrames.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "drivers/recording_format.h"

namespace ihf {

struct RecordingWriterOptions {
	bool compress = false; // zlib per frame (kept raw when that is not smaller)
	int zlibLevel = 1; // 1 = fastest; enough for depth maps
	size_t reserveFrames = 0; // index capacity to reserve (no growth up to it)
};

// The fields of one frame besides its pixels.
struct FrameStamp {
	uint64_t index = 0;
	int64_t deviceTimestampNs = 0;
	int64_t hostTimestampNs = 0;
};

class RecordingWriter
{
public:
	static Expected<RecordingWriter> create(const std::filesystem::path &file,
						const recording::RecordingHeader &header,
						const RecordingWriterOptions &options = {});

	RecordingWriter(RecordingWriter &&other) noexcept;
	RecordingWriter &operator=(RecordingWriter &&other) noexcept;
	~RecordingWriter();

	// depth must be width x height of the header; frame indices must increase.
	Status append(const FrameStamp &stamp, ImageView<const uint16_t> depth);
	// Writes the index and footer, syncs, renames into place.
	Status finish();

	size_t framesWritten() const { return index_.size(); }
	uint64_t bytesWritten() const { return offset_; }
	const std::filesystem::path &file() const { return file_; }

private:
	struct FileCloser {
		void operator()(std::FILE *f) const { std::fclose(f); }
	};

	RecordingWriter() = default;
	void abandon();
	Status writeBytes(const void *data, size_t size);

	std::filesystem::path file_;
	std::filesystem::path tmp_;
	std::unique_ptr<std::FILE, FileCloser> stream_;
	recording::RecordingHeader header_;
	RecordingWriterOptions options_;
	std::vector<uint8_t> raw_; // one frame, little-endian rows
	std::vector<uint8_t> packed_; // zlib output, deflateBound(raw) bytes
	recording::ZlibStreamsPtr deflater_;
	std::vector<recording::IndexEntry> index_;
	uint64_t offset_ = 0;
	bool finished_ = false;
};

} // namespace ihf
