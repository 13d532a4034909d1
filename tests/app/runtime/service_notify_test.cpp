// SPDX-License-Identifier: MIT
// The systemd watchdog of `ihf run`: the loop beats on every iteration and
// while it waits to reopen a source (so a stuck loop, not a slow one, is
// what the watchdog catches); the notifier sends READY=1 with the first
// beat, WATCHDOG=1 with every other one and STOPPING=1 at the end, as
// datagrams to the socket NOTIFY_SOCKET names (here a socket of the test's
// own, as systemd would bind one).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "drivers/recording_source.h"
#include "drivers/recording_writer.h"
#include "firmware_app/runtime/run_loop.h"
#include "firmware_app/runtime/service_notify.h"
#include "tests/app/small_recording.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kOneMs = 1'000'000;

// Simulated time; sleeping jumps to the deadline.
class JumpClock : public PacingClock
{
public:
	int64_t nowNs() override { return now_; }
	void sleepUntil(int64_t ns) override { now_ = std::max(now_, ns); }

private:
	int64_t now_ = 0;
};

class NoOp : public FrameProcessor
{
public:
	Status prepare(const SourceInfo &) override { return {}; }
	Status process(const Frame &, int64_t) override
	{
		++frames;
		return {};
	}
	void describe(std::string &) const override {}
	int frames = 0;
};

class BeatLog : public LoopHeartbeat
{
public:
	explicit BeatLog(PacingClock &clock) : clock_(clock) {}
	void beat() override { times.push_back(clock_.nowNs()); }
	std::vector<int64_t> times;

private:
	PacingClock &clock_;
};

void writeFrames(const fs::path &file, int n)
{
	test::writeSmallRecording(file, n, "heartbeat test");
}

TEST(LoopHeartbeat, EveryIterationAndThroughTheReopenWaits)
{
	// No file: the first open and every reopen fail.
	const fs::path dir = test::freshTempDir("heartbeat");
	JumpClock clock;
	RecordingSource source(dir / "absent.rec", {Pacing::kStep, 1.0, &clock});
	NoOp proc;
	RunLoopConfig cfg;
	cfg.maxRetries = 3;
	cfg.backoff = std::chrono::milliseconds(400);
	cfg.backoffMax = std::chrono::milliseconds(400);
	std::FILE *log = std::tmpfile();
	RunLoop loop(source, proc, clock, cfg, nullptr, log);
	BeatLog beats(clock);
	loop.setHeartbeat(&beats);
	EXPECT_EQ(loop.run(), RunEnd::kSourceFailed); // 3 waits of 400 ms, then given up
	std::fclose(log);
	// Beats all through the waits, never more than a 50 ms slice apart.
	ASSERT_GE(beats.times.size(), 3u * 8u);
	for (size_t i = 1; i < beats.times.size(); ++i)
		EXPECT_LE(beats.times[i] - beats.times[i - 1], 50 * kOneMs) << "beat " << i;
	EXPECT_GE(beats.times.back(), 1200 * kOneMs - 50 * kOneMs);
}

TEST(LoopHeartbeat, OneBeatPerFrameAtLeast)
{
	const fs::path dir = test::freshTempDir("heartbeat_frames");
	ASSERT_NO_FATAL_FAILURE(writeFrames(dir / "r.rec", 7));
	JumpClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	NoOp proc;
	std::FILE *log = std::tmpfile();
	RunLoop loop(source, proc, clock, RunLoopConfig{}, nullptr, log);
	BeatLog beats(clock);
	loop.setHeartbeat(&beats);
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	std::fclose(log);
	EXPECT_EQ(proc.frames, 7);
	EXPECT_EQ(beats.times.size(), 8u); // 7 frames and the end of the stream
}

// A datagram socket bound where NOTIFY_SOCKET points, closed and unlinked
// at the end.
class NotifySocket
{
public:
	explicit NotifySocket(const fs::path &path) : path_(path)
	{
		fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", path.c_str());
		bound_ = fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr *>(&a), sizeof(a)) == 0;
	}
	~NotifySocket()
	{
		if (fd_ >= 0)
			::close(fd_);
		::unlink(path_.c_str());
	}
	bool bound() const { return bound_; }
	// Every datagram waiting, without blocking.
	std::vector<std::string> drain()
	{
		std::vector<std::string> got;
		char buf[512];
		for (;;) {
			const ssize_t n = ::recv(fd_, buf, sizeof(buf), MSG_DONTWAIT);
			if (n < 0)
				break;
			got.emplace_back(buf, static_cast<size_t>(n));
		}
		return got;
	}

private:
	fs::path path_;
	int fd_ = -1;
	bool bound_ = false;
};

TEST(ServiceNotifier, ReadyWatchdogAndStoppingOnTheNotifySocket)
{
	if (!ServiceNotifier::available())
		GTEST_SKIP() << "built without libsystemd: ihf run sends no notifications";
	const fs::path dir = test::freshTempDir("notify");
	NotifySocket sock(dir / "notify.sock");
	ASSERT_TRUE(sock.bound());
	::setenv("NOTIFY_SOCKET", (dir / "notify.sock").c_str(), 1);
	ServiceNotifier n;
	EXPECT_TRUE(n.active());
	n.beat();
	n.beat();
	n.beat();
	n.stopping();
	::unsetenv("NOTIFY_SOCKET");
	EXPECT_EQ(sock.drain(), (std::vector<std::string>{"READY=1\nWATCHDOG=1", "WATCHDOG=1",
							  "WATCHDOG=1", "STOPPING=1"}));
}

TEST(ServiceNotifier, SilentWithoutNotifySocket)
{
	::unsetenv("NOTIFY_SOCKET");
	ServiceNotifier n;
	EXPECT_FALSE(n.active());
	n.beat(); // nothing to send to, nothing fails
	n.stopping();
}

} // namespace
} // namespace ihf::app
