// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/box_feed.h"

#include <cerrno>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/common/errno_text.h"

namespace ihf::app {

namespace {

constexpr size_t kLineCapacity = 1 << 16; // longest line accepted
constexpr double kMaxBoxCoordinate = 1e6; // pixels; frames are at most 16384 wide
constexpr size_t kReservedBoxes = 64;

} // namespace

Expected<std::unique_ptr<BoxFeed>> BoxFeed::open(const std::string &spec, ShutdownSignal *shutdown)
{
	std::unique_ptr<BoxFeed> f(new BoxFeed());
	f->spec_ = spec;
	f->shutdown_ = shutdown;
	f->buf_.resize(kLineCapacity);
	f->pending_.reserve(kReservedBoxes);
	f->current_.reserve(kReservedBoxes);
	f->parsed_.reserve(kReservedBoxes);

	if (spec == "stdin") {
		f->name_ = "boxes on stdin";
		f->fd_ = STDIN_FILENO;
		struct stat st;
		// A redirected file is read like a file; a pipe or terminal is live.
		f->live_ = !(fstat(f->fd_, &st) == 0 && S_ISREG(st.st_mode));
	} else if (spec.rfind("file:", 0) == 0) {
		const std::string path = spec.substr(5);
		f->name_ = path;
		f->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
		if (f->fd_ < 0)
			return makeError(Errc::kNotFound, path + ": cannot open the boxes file: " + errnoText(errno));
		f->ownsFd_ = true;
	} else if (spec.rfind("unix:", 0) == 0) {
		const std::string path = spec.substr(5);
		f->name_ = "boxes socket " + path;
		sockaddr_un addr{};
		addr.sun_family = AF_UNIX;
		if (path.empty() || path.size() >= sizeof(addr.sun_path))
			return makeError(Errc::kInvalidArgument, spec + ": socket path empty or too long");
		std::memcpy(addr.sun_path, path.c_str(), path.size());
		struct stat st;
		// A socket file left by an earlier run is replaced; any other file is not.
		if (lstat(path.c_str(), &st) == 0) {
			if (!S_ISSOCK(st.st_mode))
				return makeError(Errc::kInvalidArgument, path + ": exists and is not a socket");
			unlink(path.c_str());
		}
		f->listenFd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
		if (f->listenFd_ < 0 || bind(f->listenFd_, reinterpret_cast<sockaddr *>(&addr), sizeof(addr)) != 0 ||
		    listen(f->listenFd_, 1) != 0)
			return makeError(Errc::kIo, path + ": cannot listen on the boxes socket: " + errnoText(errno));
		f->socketPath_ = path;
		f->live_ = true;
	} else {
		return makeError(Errc::kInvalidArgument,
				 "boxes input '" + spec + "': use stdin, file:PATH or unix:PATH");
	}
	return f;
}

BoxFeed::~BoxFeed()
{
	if (fd_ >= 0 && (ownsFd_ || listenFd_ >= 0))
		close(fd_);
	if (listenFd_ >= 0) {
		close(listenFd_);
		unlink(socketPath_.c_str());
	}
}

void BoxFeed::dropClient()
{
	close(fd_);
	fd_ = -1;
	begin_ = end_ = 0;
}

Expected<BoxWait> BoxFeed::readLine(std::chrono::steady_clock::time_point deadline)
{
	for (;;) {
		if (fd_ >= 0) {
			const char *b = buf_.data() + begin_;
			const void *nl = std::memchr(b, '\n', end_ - begin_);
			if (nl) {
				const size_t n = static_cast<const char *>(nl) - b;
				line_ = std::string_view(b, n);
				begin_ += n + 1;
				++lineNo_;
				return BoxWait::kBoxes;
			}
			// Make room: move the partial line to the front.
			if (begin_ > 0) {
				std::memmove(buf_.data(), b, end_ - begin_);
				end_ -= begin_;
				begin_ = 0;
			}
			if (end_ == buf_.size()) {
				++lineNo_;
				problems_.push_back(name_ + " line " + std::to_string(lineNo_) + ": longer than " +
						    std::to_string(buf_.size()) + " bytes; dropped");
				++counters_.malformed;
				begin_ = end_ = 0; // the rest of it is skipped as a malformed line
				continue;
			}
		}
		if (shutdown_ && shutdown_->requested())
			return BoxWait::kShutdown;

		// Wait for data (live inputs) up to the deadline.
		pollfd fds[2];
		nfds_t n = 0;
		const bool waitingForClient = fd_ < 0;
		fds[n++] = {waitingForClient ? listenFd_ : fd_, POLLIN, 0};
		if (shutdown_ && shutdown_->valid())
			fds[n++] = {shutdown_->fd(), POLLIN, 0};
		int timeoutMs = -1;
		if (live_) {
			const auto left = std::chrono::ceil<std::chrono::milliseconds>(
				deadline - std::chrono::steady_clock::now());
			timeoutMs = static_cast<int>(std::max<int64_t>(0, left.count()));
		}
		const int r = poll(fds, n, timeoutMs);
		if (r < 0) {
			if (errno == EINTR)
				continue;
			return makeError(Errc::kIo, name_ + ": poll failed: " + errnoText(errno));
		}
		if (n > 1 && fds[1].revents)
			continue; // the shutdown check above reports it
		if (r == 0)
			return BoxWait::kNone; // timed out
		if (waitingForClient) {
			fd_ = accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
			if (fd_ >= 0)
				++counters_.clients;
			begin_ = end_ = 0;
			continue;
		}
		const ssize_t got = read(fd_, buf_.data() + end_, buf_.size() - end_);
		if (got < 0) {
			if (errno == EINTR || errno == EAGAIN)
				continue;
			if (listenFd_ >= 0) {
				dropClient();
				continue;
			}
			return makeError(Errc::kIo, name_ + ": read failed: " + errnoText(errno));
		}
		if (got == 0) {
			// A last line without '\n' still counts.
			// (end_ < size here: a full buffer was handled above.)
			if (end_ > begin_) {
				buf_[end_++] = '\n';
				continue;
			}
			if (listenFd_ >= 0) {
				dropClient(); // the detector went away; wait for the next one
				continue;
			}
			ended_ = true;
			return BoxWait::kEnd;
		}
		end_ += static_cast<size_t>(got);
	}
}

void BoxFeed::parseLine(std::string_view line, uint64_t &frame, bool &ok)
{
	ok = false;
	parsed_.clear();
	while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
		line.remove_suffix(1);
	if (line.empty())
		return;
	const std::string where = name_ + " line " + std::to_string(lineNo_) + ": ";
	nlohmann::json j = nlohmann::json::parse(line.begin(), line.end(), nullptr, false);
	if (j.is_discarded() || !j.is_object()) {
		problems_.push_back(where + "not a JSON object");
		++counters_.malformed;
		return;
	}
	auto fIt = j.find("frame");
	if (fIt == j.end() || !fIt->is_number_unsigned()) {
		problems_.push_back(where + "\"frame\" must be a non-negative integer");
		++counters_.malformed;
		return;
	}
	frame = fIt->get<uint64_t>();
	auto bIt = j.find("boxes");
	if (bIt == j.end() || !bIt->is_array()) {
		problems_.push_back(where + "\"boxes\" must be an array");
		++counters_.malformed;
		return;
	}
	ok = true;
	int i = 0;
	for (const auto &b : *bIt) {
		const std::string boxWhere = where + "box " + std::to_string(i++) + ": ";
		if (!b.is_object()) {
			problems_.push_back(boxWhere + "not an object");
			++counters_.malformed;
			continue;
		}
		auto o = b.find("obj_id");
		auto bb = b.find("bbox");
		if (o == b.end() || !o->is_number_integer() || o->get<int64_t>() < 0 ||
		    o->get<int64_t>() > 1000000) {
			problems_.push_back(boxWhere + "\"obj_id\" must be a non-negative integer");
			++counters_.malformed;
			continue;
		}
		FrameBox fb;
		fb.objId = o->get<int>();
		bool good = bb != b.end() && bb->is_array() && bb->size() == 4;
		for (size_t k = 0; good && k < 4; ++k) {
			// Boxes become int pixel boxes: a coordinate beyond any frame
			// (kMaxBoxCoordinate) is malformed, not converted.
			good = (*bb)[k].is_number() && std::abs((*bb)[k].get<double>()) <= kMaxBoxCoordinate;
			if (good)
				fb.bbox[k] = (*bb)[k].get<double>();
		}
		if (!good || fb.bbox[2] <= 0 || fb.bbox[3] <= 0) {
			problems_.push_back(boxWhere + "\"bbox\" must be [x, y, w, h] with w, h > 0, each within +-1e6");
			++counters_.malformed;
			continue;
		}
		if (auto tr = b.find("track_id"); tr != b.end()) {
			if (!tr->is_number_integer() || tr->get<int64_t>() < 1 || tr->get<int64_t>() > 1000000000) {
				problems_.push_back(boxWhere + "\"track_id\" must be a positive integer");
				++counters_.malformed;
				continue;
			}
			fb.trackId = tr->get<int>();
		}
		parsed_.push_back(fb);
	}
}

Expected<BoxWait> BoxFeed::wait(uint64_t frame, std::chrono::milliseconds timeout)
{
	current_.clear();
	problems_.clear();
	const auto deadline = std::chrono::steady_clock::now() + timeout;
	for (;;) {
		if (havePending_) {
			if (pendingFrame_ > frame)
				return BoxWait::kNone;
			havePending_ = false;
			if (pendingFrame_ == frame) {
				current_.swap(pending_);
				return BoxWait::kBoxes;
			}
			++counters_.skipped;
		}
		if (ended_)
			return BoxWait::kEnd;
		Expected<BoxWait> r = readLine(deadline);
		if (!r)
			return r;
		if (*r != BoxWait::kBoxes)
			return r;
		++counters_.lines;
		uint64_t lineFrame = 0;
		bool ok = false;
		parseLine(line_, lineFrame, ok);
		if (!ok)
			continue;
		pending_.swap(parsed_);
		pendingFrame_ = lineFrame;
		havePending_ = true;
	}
}

} // namespace ihf::app
