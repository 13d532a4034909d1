// SPDX-License-Identifier: MIT
// The `ihf run` frame loop on simulated time: step mode processes every
// frame; real-time replay drops the frames that are older than the budget
// at their turn (the expected set worked out by hand below); a source that
// fails is reported, backed off exponentially and reopened, and given up
// after the configured attempts; an unplugged USB sensor is waited for and
// the source reopened when it returns; SIGTERM stops the loop at a frame
// boundary.

#include <csignal>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/recording_source.h"
#include "drivers/recording_writer.h"
#include "firmware_app/runtime/run_loop.h"
#include "firmware_app/runtime/usb_presence.h"
#include "tests/app/small_recording.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kMs = 1'000'000;

// Simulated time: sleepUntil jumps; an optional hook runs when time passes a mark.
class SimClock : public PacingClock
{
public:
	int64_t nowNs() override { return now_; }
	void sleepUntil(int64_t deadlineNs) override
	{
		if (deadlineNs > now_)
			advance(deadlineNs - now_);
	}
	void advance(int64_t ns)
	{
		now_ += ns;
		if (hook_ && now_ >= hookAt_) {
			auto h = std::move(hook_);
			hook_ = nullptr;
			h();
		}
	}
	void at(int64_t t, std::function<void()> f) { hookAt_ = t, hook_ = std::move(f); }

private:
	int64_t now_ = 0;
	int64_t hookAt_ = 0;
	std::function<void()> hook_;
};

// Processing that takes a fixed simulated time per frame.
class CostProcessor : public FrameProcessor
{
public:
	CostProcessor(SimClock &clock, int64_t cost) : clock_(clock), cost_(cost) {}
	Status prepare(const SourceInfo &info) override
	{
		++prepared;
		width = info.intrinsics.width;
		return {};
	}
	Status process(const Frame &frame, int64_t arrivalNs) override
	{
		indices.push_back(frame.index);
		arrivals.push_back(arrivalNs);
		clock_.advance(cost_);
		if (onFrame)
			onFrame(frame);
		return {};
	}
	void describe(std::string &line) const override { line += "; test"; }

	std::vector<uint64_t> indices;
	std::vector<int64_t> arrivals;
	int prepared = 0;
	int width = 0;
	std::function<void(const Frame &)> onFrame;

private:
	SimClock &clock_;
	int64_t cost_;
};

void writeRecording(const fs::path &file, int n)
{
	test::writeSmallRecording(file, n, "run loop test");
}

class NullLog
{
public:
	NullLog() : f_(std::tmpfile()) {}
	~NullLog() { std::fclose(f_); }
	std::FILE *get() { return f_; }
	std::string text()
	{
		std::fflush(f_);
		std::rewind(f_);
		std::string s;
		char buf[4096];
		size_t n;
		while ((n = std::fread(buf, 1, sizeof(buf), f_)) > 0)
			s.append(buf, n);
		return s;
	}

private:
	std::FILE *f_;
};

TEST(RunLoop, StepModeProcessesEveryFrameInOrder)
{
	const fs::path dir = test::freshTempDir("run_loop_step");
	writeRecording(dir / "r.rec", 10);
	SimClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	CostProcessor proc(clock, 100 * kMs);
	RunLoopConfig cfg;
	cfg.frameBudget = std::chrono::milliseconds(50); // ignored in step mode
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
	EXPECT_EQ(loop.counters().late, 0u);
	EXPECT_EQ(loop.counters().processed, 10u);
	EXPECT_EQ(proc.width, 16);
	EXPECT_EQ(proc.prepared, 1);
}

TEST(RunLoop, RealTimeReplayDropsFramesOlderThanTheBudget)
{
	// 30 fps, 100 ms per frame, 50 ms budget. Frame i is due at i * 33.3 ms;
	// it is taken when the previous one is done: 0 (t 0, done 100), 1 (age
	// 66.7: late), 2 (age 33.3, done 200), 3 (100: late), 4 (66.7: late),
	// 5 (33.3, done 300), 6 late, 7 late, 8 (33.3, done 400), 9 (100: late).
	const fs::path dir = test::freshTempDir("run_loop_late");
	writeRecording(dir / "r.rec", 10);
	SimClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kRealTime, 1.0, &clock});
	CostProcessor proc(clock, 100 * kMs);
	RunLoopConfig cfg;
	cfg.realTime = true;
	cfg.frameBudget = std::chrono::milliseconds(50);
	cfg.statsInterval = std::chrono::milliseconds(150);
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices, (std::vector<uint64_t>{0, 2, 5, 8}));
	EXPECT_EQ(loop.counters().late, 6u);
	EXPECT_EQ(loop.counters().delivered, 10u);
	// Arrival = when the recording made the frame due.
	EXPECT_EQ(proc.arrivals[1], 66'666'666);
	// 150 ms passed at 200 and 400 ms: two periodic stats lines.
	const std::string text = log.text();
	size_t lines = 0;
	for (size_t p = text.find("stats:"); p != std::string::npos; p = text.find("stats:", p + 1))
		++lines;
	EXPECT_EQ(lines, 2u) << text;
	EXPECT_NE(text.find("late "), std::string::npos);
	EXPECT_NE(loop.statsLine().find("frames 10 processed 4 late 6"), std::string::npos) << loop.statsLine();
}

TEST(RunLoop, BudgetZeroNeverDrops)
{
	const fs::path dir = test::freshTempDir("run_loop_nobudget");
	writeRecording(dir / "r.rec", 5);
	SimClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kRealTime, 1.0, &clock});
	CostProcessor proc(clock, 100 * kMs);
	RunLoopConfig cfg;
	cfg.realTime = true;
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices.size(), 5u);
}

TEST(RunLoop, MissingSourceIsRetriedWithBackoffThenGivenUp)
{
	const fs::path dir = test::freshTempDir("run_loop_giveup");
	SimClock clock;
	RecordingSource source(dir / "absent.rec", {Pacing::kStep, 1.0, &clock});
	CostProcessor proc(clock, 0);
	RunLoopConfig cfg;
	cfg.maxRetries = 3;
	cfg.backoff = std::chrono::milliseconds(100);
	cfg.backoffMax = std::chrono::milliseconds(250);
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kSourceFailed);
	EXPECT_EQ(clock.nowNs(), (100 + 200 + 250) * kMs); // waits doubled, capped
	EXPECT_EQ(loop.counters().sourceErrors, 4u); // the first open and 3 reopens
	EXPECT_NE(loop.failure().find("gave up after 3 reopen attempts"), std::string::npos) << loop.failure();
	const std::string text = log.text();
	EXPECT_NE(text.find("absent.rec"), std::string::npos) << text;
	EXPECT_NE(text.find("(attempt 3 of 3)"), std::string::npos) << text;
}

TEST(RunLoop, SourceThatReturnsIsReopened)
{
	const fs::path dir = test::freshTempDir("run_loop_returns");
	writeRecording(dir / "later.rec", 4);
	fs::rename(dir / "later.rec", dir / "away.rec");
	SimClock clock;
	// The file comes back 250 ms in: the third attempt (after 100 + 200 ms) finds it.
	clock.at(250 * kMs, [&] { fs::rename(dir / "away.rec", dir / "later.rec"); });
	RecordingSource source(dir / "later.rec", {Pacing::kStep, 1.0, &clock});
	CostProcessor proc(clock, 0);
	RunLoopConfig cfg;
	cfg.maxRetries = 5;
	cfg.backoff = std::chrono::milliseconds(100);
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices.size(), 4u);
	EXPECT_EQ(loop.counters().sourceErrors, 2u);
	EXPECT_EQ(loop.counters().reopens, 1u);
	EXPECT_EQ(clock.nowNs(), 300 * kMs);
	EXPECT_NE(log.text().find("reopened"), std::string::npos);
}

// A recording that fails like an unplugged device: next() errors once at a
// given frame, then open() fails `openFailures` times; once reopened it goes
// on after the last frame it gave, as a device would.
class UnplugOnce : public FrameSource
{
public:
	UnplugOnce(RecordingSource &inner, uint64_t failAt, int openFailures)
		: inner_(inner), failAt_(failAt), openFailures_(openFailures) {}
	Status open() override
	{
		if (unplugged_ && openFailures_-- > 0)
			return makeError(Errc::kNotFound, "test device: not present");
		Status s = inner_.open();
		if (s && unplugged_)
			s = inner_.seek(last_ + 1);
		return s;
	}
	const SourceInfo &info() const override { return inner_.info(); }
	Status start() override { return inner_.start(); }
	Expected<FrameOutcome> next(Frame &f, std::chrono::nanoseconds t) override
	{
		if (!unplugged_ && delivered_ == failAt_) {
			unplugged_ = true;
			return makeError(Errc::kIo, "test device: removed");
		}
		Expected<FrameOutcome> r = inner_.next(f, t);
		if (r && *r == FrameOutcome::kFrame)
			last_ = f.index, ++delivered_;
		return r;
	}
	void stop() override { inner_.stop(); }
	SourceCounters counters() const override { return inner_.counters(); }

private:
	RecordingSource &inner_;
	uint64_t failAt_;
	int openFailures_;
	bool unplugged_ = false;
	uint64_t delivered_ = 0, last_ = 0;
};

TEST(RunLoop, DeviceErrorMidStreamIsReportedAndReopened)
{
	const fs::path dir = test::freshTempDir("run_loop_unplug");
	writeRecording(dir / "r.rec", 8);
	SimClock clock;
	RecordingSource inner(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	UnplugOnce source(inner, 3, 2);
	CostProcessor proc(clock, 0);
	RunLoopConfig cfg;
	cfg.maxRetries = 3;
	cfg.backoff = std::chrono::milliseconds(100);
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
	EXPECT_EQ(loop.counters().sourceErrors, 3u); // the removal and two failed opens
	EXPECT_EQ(loop.counters().reopens, 1u);
	EXPECT_EQ(clock.nowNs(), (100 + 200 + 400) * kMs);
	EXPECT_EQ(proc.prepared, 2);
	const std::string text = log.text();
	EXPECT_NE(text.find("test device: removed"), std::string::npos) << text;
	EXPECT_NE(text.find("test device: not present"), std::string::npos) << text;
}

TEST(RunLoop, SigtermStopsAtAFrameBoundary)
{
	const fs::path dir = test::freshTempDir("run_loop_sigterm");
	writeRecording(dir / "r.rec", 10);
	ShutdownSignal shutdown;
	ASSERT_TRUE(shutdown.valid());
	SimClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	CostProcessor proc(clock, 0);
	proc.onFrame = [](const Frame &f) {
		if (f.index == 3)
			raise(SIGTERM); // blocked: it waits in the signalfd
	};
	NullLog log;
	RunLoop loop(source, proc, clock, RunLoopConfig{}, &shutdown, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kShutdown);
	EXPECT_EQ(proc.indices.size(), 4u);
	EXPECT_EQ(shutdown.signal(), SIGTERM);
}

TEST(RunLoop, MaxFramesStops)
{
	const fs::path dir = test::freshTempDir("run_loop_max");
	writeRecording(dir / "r.rec", 10);
	SimClock clock;
	RecordingSource source(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	CostProcessor proc(clock, 0);
	RunLoopConfig cfg;
	cfg.maxFrames = 6;
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	EXPECT_EQ(loop.run(), RunEnd::kMaxFrames);
	EXPECT_EQ(proc.indices.size(), 6u);
}

// The USB bus as a list the test edits.
class ListEnumerator : public UsbEnumerator
{
public:
	Expected<std::vector<UsbDeviceEntry>> list() override { return devices; }
	bool waitForChange(std::chrono::milliseconds) override { return true; }
	std::vector<UsbDeviceEntry> devices;
};

TEST(RunLoop, UnpluggedUsbSensorIsWaitedForThenReopened)
{
	const fs::path dir = test::freshTempDir("run_loop_usb");
	writeRecording(dir / "r.rec", 8);
	ListEnumerator bus;
	const UsbDeviceEntry kinect{0x045e, 0x02d8, 2, "2-1"};
	bus.devices = {kinect};
	SimClock clock;
	RecordingSource inner(dir / "r.rec", {Pacing::kStep, 1.0, &clock});
	// Unplugged at frame 3; opens fail until it is back (after 5 s).
	UnplugOnce source(inner, 3, 0);
	CostProcessor proc(clock, 0);
	proc.onFrame = [&](const Frame &f) {
		if (f.index == 2) {
			bus.devices.clear();
			clock.at(clock.nowNs() + 5'000 * kMs, [&] { bus.devices = {kinect}; });
		}
	};
	UsbSensorPresence presence(bus, UsbSensorFilter{});
	RunLoopConfig cfg;
	cfg.maxRetries = 1; // backoff alone would give up long before 5 s
	cfg.backoff = std::chrono::milliseconds(100);
	NullLog log;
	RunLoop loop(source, proc, clock, cfg, nullptr, log.get());
	loop.setPresence(&presence, std::chrono::milliseconds(100));
	EXPECT_EQ(loop.run(), RunEnd::kEndOfStream);
	EXPECT_EQ(proc.indices, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
	EXPECT_EQ(loop.counters().unplugs, 1u);
	EXPECT_EQ(loop.counters().reopens, 1u);
	EXPECT_GE(clock.nowNs(), 5'000 * kMs);
	const std::string text = log.text();
	EXPECT_NE(text.find("USB sensor present: Microsoft Kinect v2 (045e:02d8 at 2-1)"), std::string::npos) << text;
	EXPECT_NE(text.find("USB sensor unplugged: Microsoft Kinect v2"), std::string::npos) << text;
	EXPECT_NE(text.find("waiting for it to return"), std::string::npos) << text;
	EXPECT_NE(text.find("USB sensor plugged in: Microsoft Kinect v2"), std::string::npos) << text;
	EXPECT_NE(text.find("reopened"), std::string::npos) << text;
}

} // namespace
} // namespace ihf::app
