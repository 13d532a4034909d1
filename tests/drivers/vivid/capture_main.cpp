// SPDX-License-Identifier: MIT
// ihf_v4l2_capture: runs as /init's job inside a VM whose kernel has the
// vivid test driver loaded (tests/drivers/vivid/run-vivid.sh), and checks
// ihf's V4L2 source against the real kernel:
//   capture   30 Y16 frames by mmap streaming, with a 3 ms interval timer
//             interrupting poll() (EINTR must be retried): sizes, strides,
//             indices and timestamps increasing, a real test pattern, and
//             no heap allocation in next() (operator new is counted)
//   timeout   at 1 fps (or the slowest rate vivid allows), next() with a
//             short timeout returns kTimeout, then the next frame arrives
//   bufError  vivid's "Inject V4L2_BUF_FLAG_ERROR": that buffer is skipped
//             and counted as corrupt, the stream goes on
//   removal   the device is unbound from its driver while streaming: next()
//             fails with a kIo error naming the device and saying it was
//             removed; opening fails while it is gone; after binding it
//             again, open() + start() (the caller's reconnect) gives frames
//   runLoop   ihf run's frame loop (RunLoop) on the V4L2 source: the device
//             is unbound at frame 5 and bound again 1.5 s later; the loop
//             reports the removal, reopens with backoff and goes on to 20
//             frames
// One line per check, "IHF-V4L2 CHECK <name> PASS|FAIL <detail>", and a
// last line "IHF-V4L2-RESULT PASS|FAIL"; the host-side test parses them.

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <new>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/time.h>
#include <unistd.h>

#include "drivers/clock.h"
#include "drivers/v4l2_source.h"
#include "firmware_app/runtime/run_loop.h"

using namespace ihf;

namespace {
std::atomic<bool> gCounting{false};
std::atomic<long> gAllocations{0};
} // namespace

// Test-only: C++ allocations are counted while gCounting is set.
void *operator new(std::size_t n)
{
	if (gCounting.load(std::memory_order_relaxed))
		gAllocations.fetch_add(1, std::memory_order_relaxed);
	if (void *p = std::malloc(n ? n : 1))
		return p;
	throw std::bad_alloc();
}
void operator delete(void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }

namespace {

int failures = 0;

void report(const char *name, bool pass, const std::string &detail)
{
	std::printf("IHF-V4L2 CHECK %s %s %s\n", name, pass ? "PASS" : "FAIL", detail.c_str());
	std::fflush(stdout);
	failures += !pass;
}

std::string findVividNode()
{
	for (int i = 0; i < 64; ++i) {
		const std::string path = "/dev/video" + std::to_string(i);
		const int fd = ::open(path.c_str(), O_RDWR);
		if (fd < 0)
			continue;
		v4l2_capability cap{};
		const bool ok = ioctl(fd, VIDIOC_QUERYCAP, &cap) == 0 &&
				std::strcmp(reinterpret_cast<char *>(cap.driver), "vivid") == 0 &&
				(cap.device_caps & V4L2_CAP_VIDEO_CAPTURE);
		::close(fd);
		if (ok)
			return path;
	}
	return {};
}

// A vivid control by its name, on a second handle to the device.
bool pressControl(const std::string &node, const char *name)
{
	const int fd = ::open(node.c_str(), O_RDWR);
	if (fd < 0)
		return false;
	v4l2_queryctrl q{};
	q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
	bool done = false;
	while (!done && ioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
		if (std::strcmp(reinterpret_cast<char *>(q.name), name) == 0) {
			v4l2_control c{q.id, 1};
			done = ioctl(fd, VIDIOC_S_CTRL, &c) == 0;
			break;
		}
		q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
	}
	::close(fd);
	return done;
}

volatile sig_atomic_t alarms = 0;
void onAlarm(int) { alarms = alarms + 1; }

void setTimer(long usec)
{
	itimerval t{};
	t.it_interval.tv_usec = usec;
	t.it_value.tv_usec = usec;
	setitimer(ITIMER_REAL, &t, nullptr);
}

std::string sourceUri(const std::string &node, const char *query)
{
	return node + "?format=y16" + (query ? std::string("&") + query : std::string());
}

void checkCapture(const std::string &node)
{
	auto uri = parseV4l2Uri(sourceUri(node, nullptr));
	V4l2Source src(uri->device, uri->options);
	Status st = src.open();
	if (st)
		st = src.start();
	if (!st) {
		report("capture", false, st.error().message);
		return;
	}
	const SourceInfo &info = src.info();
	const int w = info.intrinsics.width, h = info.intrinsics.height;

	struct sigaction sa{};
	sa.sa_handler = onAlarm; // no SA_RESTART: poll() returns EINTR
	sigaction(SIGALRM, &sa, nullptr);
	setTimer(3000);

	std::vector<uint64_t> idx;
	std::vector<int64_t> dev, host;
	std::string problem;
	int distinct = 0;
	SteadyPacingClock clock;
	const int64_t t0 = clock.nowNs();
	for (int i = 0; i < 30 && problem.empty(); ++i) {
		Frame f;
		gCounting = i > 0; // the first next() may set things up
		Expected<FrameOutcome> r = src.next(f, std::chrono::seconds(3));
		gCounting = false;
		if (!r) {
			problem = r.error().message;
			break;
		}
		if (*r != FrameOutcome::kFrame) {
			problem = "no frame within 3 s (frame " + std::to_string(i) + ")";
			break;
		}
		if (f.depth.width != w || f.depth.height != h || f.depth.stride * 2 != src.bytesPerLine() ||
		    f.intrinsics.width != w || !f.depth.data)
			problem = "frame size/stride does not match the format";
		if (f.depthScale != 1.0)
			problem = "depth scale is not the Y16 default of 1 mm";
		// The test pattern: count distinct values along the middle row.
		std::vector<uint16_t> row(f.depth.row(h / 2), f.depth.row(h / 2) + w);
		std::sort(row.begin(), row.end());
		distinct = std::max<int>(distinct, std::unique(row.begin(), row.end()) - row.begin());
		idx.push_back(f.index);
		dev.push_back(f.deviceTimestampNs);
		host.push_back(f.hostTimestampNs);
	}
	setTimer(0);
	const int64_t t1 = clock.nowNs();
	src.stop();
	if (problem.empty() && idx.size() != 30)
		problem = "fewer than 30 frames";
	for (size_t i = 1; problem.empty() && i < idx.size(); ++i) {
		if (idx[i] <= idx[i - 1])
			problem = "frame index not increasing at " + std::to_string(i);
		else if (dev[i] <= dev[i - 1] || host[i] <= host[i - 1])
			problem = "timestamps not increasing at " + std::to_string(i);
	}
	if (problem.empty() && (host.front() < t0 - 1'000'000'000 || host.back() > t1)) {
		char why[160];
		std::snprintf(why, sizeof(why),
			      "host timestamps are not on the steady clock (first %.1f ms after start, last %.1f ms "
			      "before the end)", (host.front() - t0) * 1e-6, (t1 - host.back()) * 1e-6);
		problem = why;
	}
	if (problem.empty() && distinct < 4)
		problem = "the frames carry no test pattern (" + std::to_string(distinct) + " values in a row)";
	if (problem.empty() && src.interruptedWaits() == 0)
		problem = "the interval timer never interrupted poll()";
	if (problem.empty() && gAllocations.load() != 0)
		problem = std::to_string(gAllocations.load()) + " heap allocations in next()";
	const double ms = idx.size() > 1 ? (dev.back() - dev.front()) * 1e-6 / (idx.size() - 1) : 0;
	char detail[320];
	std::snprintf(detail, sizeof(detail),
		      "%s %dx%d bytesperline %d, frames %zu, index %llu..%llu, dropped %llu, %.1f ms apart, "
		      "%llu EINTR retried (%d alarms), %d values in a row, %ld allocations in next(); sensor: %s",
		      src.pixelFormat().c_str(), w, h, src.bytesPerLine(), idx.size(),
		      idx.empty() ? 0ULL : static_cast<unsigned long long>(idx.front()),
		      idx.empty() ? 0ULL : static_cast<unsigned long long>(idx.back()),
		      static_cast<unsigned long long>(src.counters().dropped), ms,
		      static_cast<unsigned long long>(src.interruptedWaits()), static_cast<int>(alarms), distinct,
		      gAllocations.load(), info.sensorId.c_str());
	report("capture", problem.empty(), problem.empty() ? detail : problem + "; " + detail);
}

void checkTimeout(const std::string &node)
{
	auto uri = parseV4l2Uri(sourceUri(node, "fps=1"));
	V4l2Source src(uri->device, uri->options);
	Status st = src.open();
	if (st)
		st = src.start();
	if (!st) {
		report("timeout", false, st.error().message);
		return;
	}
	// The rate vivid granted (nearest to 1 fps it supports).
	double interval = 1.0;
	{
		const int fd = ::open(node.c_str(), O_RDWR);
		v4l2_streamparm p{};
		p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		if (fd >= 0 && ioctl(fd, VIDIOC_G_PARM, &p) == 0 && p.parm.capture.timeperframe.denominator)
			interval = double(p.parm.capture.timeperframe.numerator) / p.parm.capture.timeperframe.denominator;
		if (fd >= 0)
			::close(fd);
	}
	Frame f;
	Expected<FrameOutcome> first = src.next(f, std::chrono::seconds(5));
	const auto shortWait = std::chrono::milliseconds(static_cast<int>(interval * 1000 / 5));
	Expected<FrameOutcome> timedOut = first && *first == FrameOutcome::kFrame
						  ? src.next(f, shortWait)
						  : Expected<FrameOutcome>(FrameOutcome::kFrame);
	Expected<FrameOutcome> second = src.next(f, std::chrono::seconds(5));
	const bool pass = first && *first == FrameOutcome::kFrame && timedOut &&
			  *timedOut == FrameOutcome::kTimeout && second && *second == FrameOutcome::kFrame &&
			  src.counters().timeouts == 1;
	char detail[160];
	std::snprintf(detail, sizeof(detail), "frame interval %.3f s, timeout %lld ms -> %s, then %s; timeouts %llu",
		      interval, static_cast<long long>(shortWait.count()),
		      timedOut ? (*timedOut == FrameOutcome::kTimeout ? "kTimeout" : "a frame") : "an error",
		      second ? (*second == FrameOutcome::kFrame ? "a frame" : "no frame") : "an error",
		      static_cast<unsigned long long>(src.counters().timeouts));
	report("timeout", pass, detail);
}

void checkBufError(const std::string &node)
{
	auto uri = parseV4l2Uri(sourceUri(node, nullptr));
	V4l2Source src(uri->device, uri->options);
	Status st = src.open();
	if (st)
		st = src.start();
	if (!st) {
		report("bufError", false, st.error().message);
		return;
	}
	Frame f;
	int got = 0;
	std::string problem;
	for (int i = 0; i < 3; ++i)
		got += src.next(f, std::chrono::seconds(3)).ok();
	if (!pressControl(node, "Inject V4L2_BUF_FLAG_ERROR"))
		problem = "vivid has no 'Inject V4L2_BUF_FLAG_ERROR' control";
	uint64_t lastIndex = f.index, gapAt = 0;
	for (int i = 0; i < 8 && problem.empty(); ++i) {
		Expected<FrameOutcome> r = src.next(f, std::chrono::seconds(3));
		if (!r || *r != FrameOutcome::kFrame) {
			problem = r ? "timeout after the flagged buffer" : r.error().message;
			break;
		}
		if (f.index > lastIndex + 1)
			gapAt = f.index;
		lastIndex = f.index;
		++got;
	}
	src.stop();
	const SourceCounters c = src.counters();
	if (problem.empty() && c.corrupt != 1)
		problem = "corrupt count is " + std::to_string(c.corrupt) + ", expected 1";
	char detail[160];
	std::snprintf(detail, sizeof(detail), "%d frames delivered, corrupt %llu, dropped %llu, index gap at %llu",
		      got, static_cast<unsigned long long>(c.corrupt), static_cast<unsigned long long>(c.dropped),
		      static_cast<unsigned long long>(gapAt));
	report("bufError", problem.empty(), problem.empty() ? detail : problem + "; " + detail);
}

bool writeSys(const char *file, const char *text)
{
	const int fd = ::open(file, O_WRONLY);
	if (fd < 0)
		return false;
	const bool ok = write(fd, text, std::strlen(text)) == static_cast<ssize_t>(std::strlen(text));
	::close(fd);
	return ok;
}

void checkRemoval(std::string node)
{
	auto uri = parseV4l2Uri(sourceUri(node, nullptr));
	V4l2Source src(uri->device, uri->options);
	Status st = src.open();
	if (st)
		st = src.start();
	Frame f;
	if (!st || !src.next(f, std::chrono::seconds(3)).ok()) {
		report("removal", false, st ? "no first frame" : st.error().message);
		return;
	}
	if (!writeSys("/sys/bus/platform/drivers/vivid/unbind", "vivid.0")) {
		report("removal", false, std::string("cannot unbind vivid.0: ") + std::strerror(errno));
		return;
	}
	// Frames already queued may still come; the removal must show within a few.
	Expected<FrameOutcome> r = FrameOutcome::kFrame;
	for (int i = 0; i < 10 && r && *r != FrameOutcome::kTimeout; ++i)
		r = src.next(f, std::chrono::seconds(2));
	std::string problem;
	std::string message = r ? "" : r.error().message;
	if (r)
		problem = "next() did not fail after the device was removed";
	else if (r.error().code != Errc::kIo || message.find(node) == std::string::npos ||
		 message.find("removed") == std::string::npos)
		problem = "the error does not name the device and its removal: " + message;

	// The caller's reconnect policy: stop, then open() until it is back.
	src.stop();
	Status whileGone = src.open();
	if (problem.empty() && whileGone)
		problem = "open() succeeded while the device was unbound";
	const std::string goneMessage = whileGone ? "" : whileGone.error().message;
	if (!writeSys("/sys/bus/platform/drivers/vivid/bind", "vivid.0") && problem.empty())
		problem = std::string("cannot bind vivid.0 again: ") + std::strerror(errno);
	int frames = 0;
	if (problem.empty()) {
		node = findVividNode();
		Status again = src.open(); // the URI names the old node; vivid comes back on the same one
		if (again)
			again = src.start();
		if (!again)
			problem = "reopen after the device returned failed: " + again.error().message +
				  " (vivid is now at " + node + ")";
		for (int i = 0; i < 5 && problem.empty(); ++i) {
			Expected<FrameOutcome> g = src.next(f, std::chrono::seconds(3));
			if (g && *g == FrameOutcome::kFrame)
				++frames;
		}
		if (problem.empty() && frames != 5)
			problem = "only " + std::to_string(frames) + " of 5 frames after reconnecting";
		src.stop();
	}
	report("removal", problem.empty(),
	       (problem.empty() ? std::string() : problem + "; ") + "error: " + message +
		       " | while gone: " + goneMessage + " | after rebind: " + std::to_string(frames) + " frames");
}

// Counts frames; unbinds the device at frame 5 and binds it again later.
class UnbindingProcessor : public app::FrameProcessor
{
public:
	Status prepare(const SourceInfo &) override
	{
		++prepared;
		return {};
	}
	Status process(const Frame &, int64_t) override
	{
		if (++frames == 5) {
			unbound = writeSys("/sys/bus/platform/drivers/vivid/unbind", "vivid.0");
			rebinder = std::thread([this] {
				std::this_thread::sleep_for(std::chrono::milliseconds(1500));
				rebound = writeSys("/sys/bus/platform/drivers/vivid/bind", "vivid.0");
			});
		}
		return {};
	}
	void describe(std::string &) const override {}

	int frames = 0, prepared = 0;
	bool unbound = false;
	std::atomic<bool> rebound{false};
	std::thread rebinder;
};

void checkRunLoop(const std::string &node)
{
	auto uri = parseV4l2Uri(sourceUri(node, nullptr));
	V4l2Source src(uri->device, uri->options);
	UnbindingProcessor proc;
	SteadyPacingClock clock;
	app::RunLoopConfig cfg;
	cfg.timeout = std::chrono::seconds(2);
	cfg.maxRetries = 8;
	cfg.backoff = std::chrono::milliseconds(100);
	cfg.backoffMax = std::chrono::milliseconds(800);
	cfg.maxFrames = 20;
	cfg.statsInterval = std::chrono::nanoseconds(0);
	std::FILE *log = std::tmpfile();
	app::RunLoop loop(src, proc, clock, cfg, nullptr, log);
	const app::RunEnd end = loop.run();
	if (proc.rebinder.joinable())
		proc.rebinder.join();
	std::string text;
	std::rewind(log);
	char buf[512];
	while (std::fgets(buf, sizeof(buf), log))
		text += buf;
	std::fclose(log);
	const app::RunCounters &c = loop.counters();
	std::string problem;
	if (!proc.unbound || !proc.rebound)
		problem = "could not unbind/bind vivid.0";
	else if (end != app::RunEnd::kMaxFrames)
		problem = std::string("the loop ended with ") + app::runEndName(end) + ": " + loop.failure();
	else if (c.reopens != 1 || c.sourceErrors < 2 || proc.prepared != 2)
		problem = "expected one removal, failed reopens while unbound, then one reopen";
	else if (text.find("was removed") == std::string::npos || text.find("reopened") == std::string::npos)
		problem = "the log does not report the removal and the reopen";
	for (char &ch : text)
		if (ch == '\n')
			ch = '|';
	report("runLoop", problem.empty(),
	       (problem.empty() ? std::string() : problem + "; ") + "frames " + std::to_string(c.delivered) +
		       ", source errors " + std::to_string(c.sourceErrors) + ", reopens " +
		       std::to_string(c.reopens) + "; log: " + text);
}

} // namespace

int main()
{
	const std::string node = findVividNode();
	report("node", !node.empty(), node.empty() ? "no vivid capture node in /dev/video*" : node);
	if (!node.empty()) {
		checkCapture(node);
		checkTimeout(node);
		checkBufError(node);
		checkRemoval(node); // these two unbind the device and bind it again
		checkRunLoop(node);
	}
	std::printf("IHF-V4L2-RESULT %s\n", failures ? "FAIL" : "PASS");
	std::fflush(stdout);
	return failures ? 1 : 0;
}
