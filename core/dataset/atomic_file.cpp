// SPDX-License-Identifier: MIT
#include "core/dataset/atomic_file.h"

#include "core/common/special_file.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

#include "core/common/errno_text.h"

namespace ihf {

namespace fs = std::filesystem;

namespace {

// Removes the temporary file unless released, so every early return cleans up.
class TempGuard
{
public:
	explicit TempGuard(fs::path path) : path_(std::move(path)) {}
	~TempGuard()
	{
		if (stream_)
			std::fclose(stream_);
		if (!released_) {
			std::error_code ec;
			fs::remove(path_, ec);
		}
	}
	TempGuard(const TempGuard &) = delete;
	TempGuard &operator=(const TempGuard &) = delete;

	std::FILE *stream_ = nullptr;
	void release() { released_ = true; }

private:
	fs::path path_;
	bool released_ = false;
};

} // namespace

Status writeFileAtomic(const fs::path &file,
		       const std::function<Status(std::FILE *stream)> &fill)
{
	if (file.empty() || !file.has_filename())
		return makeError(Errc::kInvalidArgument,
				 file.string() + ": not a file path (no file name)");

	std::error_code ec;
	if (fs::is_directory(file, ec))
		return makeError(Errc::kInvalidArgument,
				 file.string() + ": is a directory, cannot write a file there");

	if (isSpecialFile(file)) { // a device or FIFO: written in place
		std::FILE *stream = std::fopen(file.c_str(), "wb");
		if (!stream)
			return makeError(Errc::kIo, file.string() + ": cannot open: " + errnoText(errno));
		Status filled = fill(stream);
		const bool flushed = filled && std::fflush(stream) == 0 && !std::ferror(stream);
		const int err = errno;
		const bool closed = std::fclose(stream) == 0;
		if (!filled)
			return filled.error();
		if (!flushed || !closed)
			return makeError(Errc::kIo, file.string() + ": write failed: " + errnoText(flushed ? errno : err));
		return {};
	}

	const fs::path parent = file.parent_path();
	if (!parent.empty()) {
		fs::create_directories(parent, ec);
		if (ec)
			return makeError(Errc::kIo, file.string() + ": cannot create folder " +
						    parent.string() + ": " + ec.message());
	}

	// pid separates processes, the counter separates threads of one process.
	static std::atomic<unsigned> counter{0};
	fs::path tmp = file;
	tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);

	TempGuard guard(tmp);
	guard.stream_ = std::fopen(tmp.c_str(), "wb");
	if (!guard.stream_) {
		int err = errno;
		guard.release(); // nothing was created
		return makeError(Errc::kIo, file.string() + ": cannot create temporary file " +
					    tmp.string() + ": " + errnoText(err));
	}

	Status filled = fill(guard.stream_);
	if (!filled)
		return filled.error();

	bool flushed = std::fflush(guard.stream_) == 0 && !std::ferror(guard.stream_);
	int err = errno;
	int closed = std::fclose(guard.stream_);
	if (!flushed || closed != 0) {
		if (flushed)
			err = errno;
		guard.stream_ = nullptr;
		return makeError(Errc::kIo, file.string() + ": write failed: " + errnoText(err));
	}
	guard.stream_ = nullptr;

	// No fsync: the outputs are reproducible, rename gives the all-or-nothing
	// visibility we need without paying for durability on every frame file.
	fs::rename(tmp, file, ec);
	if (ec)
		return makeError(Errc::kIo, file.string() + ": cannot rename temporary file into place: " +
					    ec.message());
	guard.release();
	return {};
}

Status writeFileAtomic(const fs::path &file, std::string_view contents)
{
	return writeFileAtomic(file, [&](std::FILE *stream) -> Status {
		if (!contents.empty() &&
		    std::fwrite(contents.data(), 1, contents.size(), stream) != contents.size())
			return makeError(Errc::kIo, file.string() + ": write failed: " +
						    errnoText(errno));
		return {};
	});
}

} // namespace ihf
