// SPDX-License-Identifier: MIT
#pragma once

// The boxes of an upstream detector, one JSON line per frame:
//   {"frame": 12, "boxes": [{"obj_id": 20, "bbox": [x, y, w, h]}, ...]}
// A box may carry the detector's own "track_id" (a positive integer): the
// tracker then follows that identity instead of matching by overlap.
// from a file ("file:PATH"), standard input ("stdin") or a UNIX stream
// socket ("unix:PATH": ihf listens there and serves one client at a time;
// poses can go back on the same connection). Lines come in increasing frame
// order. boxesFor(i) skips lines of frames before i (frames that were
// dropped or had no turn), keeps a line of a later frame for later, and for
// live inputs (a pipe, a socket) waits up to a timeout for frame i's line.
// A line that does not parse, or a box in it that is malformed, is reported
// through problems() (with the line number) and the rest goes on.
//
// Lines are read into a fixed buffer; JSON parsing (nlohmann) allocates, as
// does a frame with more boxes than reserved: the box input is the one place
// of the frame path that may.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "firmware_app/runtime/frame_box.h"
#include "firmware_app/runtime/shutdown_signal.h"

namespace ihf::app {

struct BoxFeedCounters {
	uint64_t lines = 0; // lines read
	uint64_t skipped = 0; // lines of frames already passed
	uint64_t malformed = 0; // lines or boxes that did not parse
	uint64_t clients = 0; // unix socket: connections accepted
};

enum class BoxWait {
	kBoxes, // the frame's line arrived (it may list no boxes)
	kNone, // no line for this frame: the input moved past it, or the wait timed out
	kEnd, // the input ended (file or stdin at EOF)
	kShutdown, // SIGINT/SIGTERM arrived while waiting
};

class BoxFeed
{
public:
	static Expected<std::unique_ptr<BoxFeed>> open(const std::string &spec,
						       ShutdownSignal *shutdown = nullptr);
	~BoxFeed();
	BoxFeed(const BoxFeed &) = delete;
	BoxFeed &operator=(const BoxFeed &) = delete;

	// Boxes of the frame with this index, in boxes() on kBoxes.
	Expected<BoxWait> wait(uint64_t frame, std::chrono::milliseconds timeout);
	std::span<const FrameBox> boxes() const { return {current_.data(), current_.size()}; }
	// Problems met during the last wait(), as "SOURCE line N: what".
	std::span<const std::string> problems() const { return problems_; }

	bool live() const { return live_; }
	// The connected client of a unix socket, -1 otherwise or when none.
	int clientFd() const { return listenFd_ >= 0 ? fd_ : -1; }
	const std::string &spec() const { return spec_; }
	const BoxFeedCounters &counters() const { return counters_; }

private:
	BoxFeed() = default;
	// One complete line into line_ (without '\n'); false on timeout/EOF/shutdown.
	Expected<BoxWait> readLine(std::chrono::steady_clock::time_point deadline);
	void parseLine(std::string_view line, uint64_t &frame, bool &ok);
	void dropClient();

	std::string spec_;
	std::string name_; // for messages
	ShutdownSignal *shutdown_ = nullptr;
	int fd_ = -1;
	bool ownsFd_ = false;
	int listenFd_ = -1;
	std::string socketPath_;
	bool live_ = false;
	bool ended_ = false;
	std::vector<char> buf_; // fixed at open
	size_t begin_ = 0, end_ = 0;
	std::string_view line_;
	uint64_t lineNo_ = 0;
	bool havePending_ = false;
	uint64_t pendingFrame_ = 0;
	std::vector<FrameBox> pending_, current_, parsed_;
	std::vector<std::string> problems_;
	BoxFeedCounters counters_;
};

} // namespace ihf::app
