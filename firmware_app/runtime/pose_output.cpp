// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/pose_output.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "core/common/special_file.h"
#include "firmware_app/runtime/box_feed.h"

namespace ihf::app {

namespace {

// Appends to a fixed buffer; overflow is remembered, never written past.
class LineBuilder
{
public:
	LineBuilder(char *buf, size_t cap) : buf_(buf), cap_(cap) {}

	void text(std::string_view s)
	{
		if (size_ + s.size() >= cap_) {
			overflow_ = true;
			return;
		}
		std::memcpy(buf_ + size_, s.data(), s.size());
		size_ += s.size();
	}
	template<typename T>
	void number(T v)
	{
		auto [ptr, ec] = std::to_chars(buf_ + size_, buf_ + cap_ - 1, v);
		if (ec != std::errc()) {
			overflow_ = true;
			return;
		}
		size_ = ptr - buf_;
	}
	// A JSON string body: quotes, backslashes and control characters escaped.
	void escaped(std::string_view s)
	{
		for (char c : s) {
			const unsigned char u = static_cast<unsigned char>(c);
			if (c == '"' || c == '\\') {
				char e[2] = {'\\', c};
				text({e, 2});
			} else if (u < 0x20) {
				char e[7];
				std::snprintf(e, sizeof(e), "\\u%04x", u);
				text(e);
			} else {
				text({&c, 1});
			}
		}
	}
	size_t size() const { return size_; }
	bool overflow() const { return overflow_; }

private:
	char *buf_;
	size_t cap_;
	size_t size_ = 0;
	bool overflow_ = false;
};

} // namespace

Expected<std::unique_ptr<PoseOutput>> PoseOutput::open(const std::string &spec, const BoxFeed *feed)
{
	std::unique_ptr<PoseOutput> o(new PoseOutput());
	o->spec_ = spec;
	if (spec == "stdout") {
		o->fd_ = STDOUT_FILENO;
	} else if (spec == "socket") {
		if (!feed || feed->spec().rfind("unix:", 0) != 0)
			return makeError(Errc::kInvalidArgument,
					 "poses output 'socket' needs the boxes input to be unix:PATH");
		o->feed_ = feed;
	} else if (spec.rfind("file:", 0) == 0 && spec.size() > 5) {
		o->path_ = spec.substr(5);
		// A device or FIFO is written in place; a file through a
		// temporary renamed over it at the end.
		if (!isSpecialFile(o->path_))
			o->tmp_ = o->path_ + ".tmp-" + std::to_string(getpid());
		o->fd_ = o->tmp_.empty() ? ::open(o->path_.c_str(), O_WRONLY | O_CLOEXEC)
					 : ::open(o->tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
		if (o->fd_ < 0)
			return makeError(Errc::kIo, o->path_ + ": cannot write the poses: " + std::strerror(errno));
		o->ownsFd_ = true;
	} else {
		return makeError(Errc::kInvalidArgument,
				 "poses output '" + spec + "': use stdout, file:PATH or socket");
	}
	return o;
}

PoseOutput::~PoseOutput()
{
	if (ownsFd_ && fd_ >= 0) {
		close(fd_);
		if (!tmp_.empty()) // not finished: no half file under the final name
			unlink(tmp_.c_str());
	}
}

Status PoseOutput::writeLine(size_t size)
{
	const int fd = feed_ ? feed_->clientFd() : fd_;
	if (fd < 0) {
		++lost_; // no client connected
		return {};
	}
	size_t done = 0;
	while (done < size) {
		const ssize_t n = feed_ ? send(fd, line_ + done, size - done, MSG_NOSIGNAL)
					: write(fd, line_ + done, size - done);
		if (n < 0 && errno == EINTR)
			continue;
		if (n <= 0) {
			if (feed_) {
				++lost_; // the client went away; the feed notices and waits for the next
				return {};
			}
			return makeError(Errc::kIo, (path_.empty() ? spec_ : path_) +
							   ": writing poses failed: " + std::strerror(errno));
		}
		done += static_cast<size_t>(n);
	}
	++written_;
	return {};
}

Status PoseOutput::writePose(const PoseLine &p)
{
	const PoseEstimate &e = *p.estimate;
	LineBuilder b(line_, sizeof(line_));
	b.text("{\"frame\":");
	b.number(p.frame);
	b.text(",\"obj_id\":");
	b.number(p.objId);
	b.text(",\"R\":[");
	for (int i = 0; i < 9; ++i) {
		if (i)
			b.text(",");
		b.number(e.pose.R(i / 3, i % 3));
	}
	b.text("],\"t\":[");
	for (int i = 0; i < 3; ++i) {
		if (i)
			b.text(",");
		b.number(e.pose.t(i));
	}
	b.text("],\"confidence\":");
	b.number(static_cast<double>(e.confidence));
	b.text(",\"score\":");
	b.number(static_cast<double>(e.score.score));
	b.text(",\"margin\":");
	b.number(static_cast<double>(e.margin));
	b.text(",\"iterations\":");
	b.number(e.iterationsDone);
	b.text(",\"best_iteration\":");
	b.number(e.bestIteration);
	b.text(e.icpApplied ? ",\"icp\":true" : ",\"icp\":false");
	if (e.ambiguous) {
		b.text(",\"ambiguous\":true,\"ambiguity_axis\":[");
		for (int i = 0; i < 3; ++i) {
			if (i)
				b.text(",");
			b.number(e.ambiguityAxis(i));
		}
		b.text("]");
	}
	b.text(",\"latency_ms\":");
	b.number(std::round(p.latencyMs * 1000) / 1000);
	b.text(",\"estimate_ms\":");
	b.number(std::round(p.estimateMs * 1000) / 1000);
	if (p.mode) {
		b.text(",\"mode\":\"");
		b.text(p.mode);
		b.text("\",\"track_id\":");
		b.number(p.trackId);
	}
	b.text("}\n");
	if (b.overflow())
		return makeError(Errc::kCapacity, "pose line longer than the line buffer");
	return writeLine(b.size());
}

Status PoseOutput::writeError(int64_t frame, int64_t objId, std::string_view message)
{
	return writeError(frame, objId, message, nullptr, 0);
}

Status PoseOutput::writeError(int64_t frame, int64_t objId, std::string_view message, const char *mode, int trackId)
{
	LineBuilder b(line_, sizeof(line_) - 8);
	b.text("{");
	if (frame >= 0) {
		b.text("\"frame\":");
		b.number(frame);
		b.text(",");
	}
	if (objId >= 0) {
		b.text("\"obj_id\":");
		b.number(objId);
		b.text(",");
	}
	if (mode) {
		b.text("\"mode\":\"");
		b.text(mode);
		b.text("\",\"track_id\":");
		b.number(trackId);
		b.text(",");
	}
	b.text("\"error\":\"");
	b.escaped(message.substr(0, 1024));
	b.text("\"}\n");
	if (b.overflow())
		return makeError(Errc::kCapacity, "error line longer than the line buffer");
	return writeLine(b.size());
}

Status PoseOutput::finish()
{
	if (!ownsFd_ || fd_ < 0)
		return {};
	if (tmp_.empty()) { // written in place
		const bool closed = close(fd_) == 0;
		fd_ = -1;
		if (!closed)
			return makeError(Errc::kIo, path_ + ": cannot finish the poses: " + std::strerror(errno));
		return {};
	}
	const bool synced = fsync(fd_) == 0;
	const bool closed = close(fd_) == 0;
	fd_ = -1;
	if (!synced || !closed || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
		const std::string why = std::strerror(errno);
		unlink(tmp_.c_str());
		return makeError(Errc::kIo, path_ + ": cannot finish the poses file: " + why);
	}
	return {};
}

} // namespace ihf::app
