// SPDX-License-Identifier: MIT
// OpenNI2 without hardware: the real libOpenNI2 loads our driver plugin
// (libihfrecdriver.so.0, which exposes a .rec recording as a depth device)
// from a private driver folder. The device is recorded to .oni with
// openni::Recorder and the .oni is played back through ihf's OpenNI2 source;
// every frame must come back bit-identical, in order, with its index.
//
// The folder (IHF_OPENNI2_ENV) holds a copy of libOpenNI2.so.0 and
// OpenNI2/Drivers/{libihfrecdriver.so.0, libOniFile.so.0}; this executable
// finds that copy first through its RUNPATH, and OpenNI2 looks for drivers
// beside the library it was loaded from.

#include <optional>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <memory>

#include <OpenNI.h>

#include "drivers/openni2_source.h"
#include "drivers/recording_reader.h"
#include "drivers/source_factory.h"
#include "tests/common/test_paths.h"
#include "tests/drivers/recording_test_util.h"

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr int kW = 160, kH = 120;

// Eight frames, indices 1..8 (the .oni recorder renumbers frames from 1),
// device timestamps 33.333 ms apart, holes, and values up to 65534. (65535
// does not survive OpenNI2's lossless depth codec: it comes back as another
// value; no depth sensor produces it.)
TestStream roundTripStream()
{
	TestStream s;
	for (int i = 0; i < 8; ++i) {
		s.indices.push_back(static_cast<uint64_t>(i + 1));
		s.deviceNs.push_back(1'000'000'000LL + i * 33'333'000LL);
		s.hostNs.push_back(i * 33'333'333LL);
		s.frames.push_back(testFrame(kW, kH, static_cast<uint32_t>(100 + i)));
		s.frames.back().at(1, 0) = 65534; // instead of 65535, see above
		s.frames.back().at(2, 0) = 40000;
		s.frames.back().at(3, 0) = 32768;
		s.frames.back().at(4, 0) = 10001;
	}
	return s;
}

class OpenNi2RoundTrip : public ::testing::Test
{
protected:
	void SetUp() override
	{
		// The library must be the private copy, or our driver is not seen.
		Dl_info where{};
		ASSERT_NE(dladdr(reinterpret_cast<void *>(&oniInitialize), &where), 0);
		const std::string loaded = fs::weakly_canonical(where.dli_fname).string();
		const std::string env = fs::weakly_canonical(IHF_OPENNI2_ENV).string();
		ASSERT_EQ(loaded.rfind(env, 0), 0u)
			<< "libOpenNI2 came from " << loaded << ", not from " << env;
		// OpenNI2 stays loaded for the whole test: recordOnce() closes the
		// .oni player, whose thread OpenNI2 cancels; its own shutdown must
		// not unload the driver while that thread unwinds (a crash seen
		// in about 1 of 10 parallel runs).
		session_.emplace();
		ASSERT_TRUE(session_->ok()) << openni::OpenNI::getExtendedError();
		// One folder per test: ctest may run them in parallel.
		dir_ = freshTempDir(std::string("openni2_") +
				    ::testing::UnitTest::GetInstance()->current_test_info()->name());
		rec_ = dir_ / "source.rec";
		stream_ = roundTripStream();
		recording::RecordingHeader h = testHeader(kW, kH);
		h.depthScale = 1.0;
		writeStream(rec_, stream_, true, h);
	}

	void TearDown() override { session_.reset(); }

	std::optional<OpenNi2Session> session_;
	fs::path dir_;
	fs::path rec_;
	TestStream stream_;
};

// Records the plugin device to oni with openni::Recorder until the last
// frame has gone by; returns the number of frames in the .oni.
int recordOnce(const fs::path &rec, const fs::path &oni, uint64_t lastIndex)
{
	using namespace openni;
	int frames = -1;
	EXPECT_EQ(OpenNI::initialize(), STATUS_OK) << OpenNI::getExtendedError();
	{
		Device device;
		const std::string uri = "ihfrec:" + rec.string();
		EXPECT_EQ(device.open(uri.c_str()), STATUS_OK) << OpenNI::getExtendedError();
		VideoStream depth;
		EXPECT_EQ(depth.create(device, SENSOR_DEPTH), STATUS_OK) << OpenNI::getExtendedError();
		Recorder recorder;
		EXPECT_EQ(recorder.create(oni.c_str()), STATUS_OK) << OpenNI::getExtendedError();
		EXPECT_EQ(recorder.attach(depth, false), STATUS_OK) << OpenNI::getExtendedError();
		EXPECT_EQ(recorder.start(), STATUS_OK);
		EXPECT_EQ(depth.start(), STATUS_OK);
		uint64_t seen = 0;
		for (int waits = 0; seen < lastIndex && waits < 100; ++waits) {
			VideoStream *streams[] = {&depth};
			int ready = -1;
			if (OpenNI::waitForAnyStream(streams, 1, &ready, 100) != STATUS_OK)
				continue;
			VideoFrameRef f;
			EXPECT_EQ(depth.readFrame(&f), STATUS_OK);
			seen = static_cast<uint64_t>(f.getFrameIndex());
		}
		EXPECT_EQ(seen, lastIndex);
		// destroy() flushes the recorder's queue and closes the file.
		recorder.stop();
		recorder.destroy();
		depth.stop();
		depth.destroy();
		device.close();

		Device file;
		VideoStream fileDepth;
		if (file.open(oni.c_str()) == STATUS_OK && fileDepth.create(file, SENSOR_DEPTH) == STATUS_OK)
			frames = file.getPlaybackControl()->getNumberOfFrames(fileDepth);
		fileDepth.destroy();
		file.close();
	}
	OpenNI::shutdown();
	return frames;
}

// openni::Recorder::start() only queues the start for the recorder's thread
// and drops frames that arrive before that thread got to it; the plugin
// waits before its first frame, and a lost first frame is retried here.
void recordToOni(const fs::path &rec, const fs::path &oni, const TestStream &s)
{
	int frames = -1;
	for (int attempt = 0; attempt < 3 && frames != static_cast<int>(s.frames.size()); ++attempt) {
		if (attempt > 0)
			std::fprintf(stderr, "note: .oni had %d of %zu frames, recording again\n", frames,
				     s.frames.size());
		frames = recordOnce(rec, oni, s.indices.back());
	}
	ASSERT_EQ(frames, static_cast<int>(s.frames.size()));
}

TEST_F(OpenNi2RoundTrip, OniRecordingPlaysBackBitIdentical)
{
	const fs::path oni = dir_ / "capture.oni";
	recordToOni(rec_, oni, stream_);
	ASSERT_TRUE(fs::exists(oni));

	auto stepped = std::make_unique<OpenNi2Source>(oni.string());
	OpenNi2Source &src = *stepped;
	Status opened = src.open();
	ASSERT_TRUE(opened.ok()) << opened.error().message;
	EXPECT_FALSE(src.info().live);
	EXPECT_EQ(src.fileFrameCount(), 8);
	EXPECT_EQ(src.info().intrinsics.width, kW);
	EXPECT_EQ(src.info().intrinsics.height, kH);
	EXPECT_EQ(src.info().depthScale, 1.0);
	// Intrinsics come back through the field of view (float), near enough.
	EXPECT_NEAR(src.info().intrinsics.fx, testHeader().intrinsics.fx, 1e-3);
	EXPECT_NEAR(src.info().intrinsics.fy, testHeader().intrinsics.fy, 1e-3);
	ASSERT_TRUE(src.start().ok());

	Frame f;
	for (size_t i = 0; i < stream_.frames.size(); ++i) {
		auto r = src.next(f, 2s);
		ASSERT_TRUE(r.ok()) << r.error().message;
		ASSERT_EQ(*r, FrameOutcome::kFrame) << "frame " << i;
		EXPECT_EQ(f.index, stream_.indices[i]);
		// The recorder stores microseconds from the first frame.
		EXPECT_EQ(f.deviceTimestampNs, stream_.deviceNs[i] - stream_.deviceNs[0]);
		EXPECT_EQ(depthDifference(f.depth, stream_.frames[i]), "") << "frame " << i;
	}
	auto end = src.next(f, 200ms);
	ASSERT_TRUE(end.ok());
	EXPECT_EQ(*end, FrameOutcome::kEndOfStream);
	EXPECT_EQ(src.counters().delivered, 8u);
	EXPECT_EQ(src.counters().dropped, 0u);
	src.stop();
	// OpenNI2 hands a second open of the same URI the same device (and its
	// played-out stream): close the first before playing again.
	stepped.reset();

	// At recorded speed (OpenNI2 paces it; ~0.25 s here) the frames are the same.
	OpenNi2SourceOptions realTime;
	realTime.realTime = true;
	OpenNi2Source paced(oni.string(), realTime);
	ASSERT_TRUE(paced.open().ok());
	ASSERT_TRUE(paced.start().ok());
	for (size_t i = 0; i < stream_.frames.size(); ++i) {
		auto r = paced.next(f, 2s);
		ASSERT_TRUE(r.ok()) << r.error().message;
		ASSERT_EQ(*r, FrameOutcome::kFrame) << "frame " << i;
		EXPECT_EQ(f.index, stream_.indices[i]);
		EXPECT_EQ(depthDifference(f.depth, stream_.frames[i]), "") << "frame " << i;
	}
	end = paced.next(f, 200ms);
	ASSERT_TRUE(end.ok());
	EXPECT_EQ(*end, FrameOutcome::kEndOfStream);
}

// Simulated time: sleeping moves "now" forward.
class SimClock : public PacingClock
{
public:
	int64_t nowNs() override { return now; }
	void sleepUntil(int64_t deadlineNs) override { now = std::max(now, deadlineNs); }
	int64_t now = 5'000'000'000;
};

// At recorded speed the file is paced by its device timestamps on the given
// clock, as a .rec replays: a frame not due within the timeout is a timeout
// (and comes on the next call), a reader that falls behind still gets every
// frame, and the stream ends after one pass.
TEST_F(OpenNi2RoundTrip, RealTimePlaybackPacesEveryFrameOnTheInjectedClock)
{
	const fs::path oni = dir_ / "capture.oni";
	recordToOni(rec_, oni, stream_);
	SimClock clock;
	OpenNi2SourceOptions realTime;
	realTime.realTime = true;
	realTime.clock = &clock;
	OpenNi2Source paced(oni.string(), realTime);
	ASSERT_TRUE(paced.open().ok());
	ASSERT_TRUE(paced.start().ok());
	const int64_t t0 = clock.now;
	Frame f;
	auto r = paced.next(f, 2s);
	ASSERT_TRUE(r.ok()) << r.error().message;
	ASSERT_EQ(*r, FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 1u);
	EXPECT_EQ(clock.now, t0); // the first frame anchors the pacing

	// Frame 2 is due 33.333 ms later: a 10 ms wait times out.
	r = paced.next(f, 10ms);
	ASSERT_TRUE(r.ok());
	EXPECT_EQ(*r, FrameOutcome::kTimeout);
	EXPECT_EQ(clock.now, t0 + 10'000'000);
	EXPECT_EQ(paced.counters().timeouts, 1u);
	r = paced.next(f, 2s);
	ASSERT_TRUE(r.ok());
	ASSERT_EQ(*r, FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 2u);
	EXPECT_EQ(clock.now, t0 + (stream_.deviceNs[1] - stream_.deviceNs[0]));
	// A .oni keeps no host time: the recording's (device) time stands for it.
	EXPECT_EQ(f.hostTimestampNs, f.deviceTimestampNs);
	EXPECT_EQ(depthDifference(f.depth, stream_.frames[1]), "");

	// The reader is busy past the last frame's time: the rest come at once, all of them.
	clock.now = t0 + 1'000'000'000;
	for (size_t i = 2; i < stream_.frames.size(); ++i) {
		r = paced.next(f, 2s);
		ASSERT_TRUE(r.ok()) << r.error().message;
		ASSERT_EQ(*r, FrameOutcome::kFrame) << "frame " << i;
		EXPECT_EQ(f.index, stream_.indices[i]);
		EXPECT_EQ(depthDifference(f.depth, stream_.frames[i]), "") << "frame " << i;
	}
	EXPECT_EQ(clock.now, t0 + 1'000'000'000);
	r = paced.next(f, 2s);
	ASSERT_TRUE(r.ok());
	EXPECT_EQ(*r, FrameOutcome::kEndOfStream);
	EXPECT_EQ(paced.counters().delivered, 8u);
	EXPECT_EQ(paced.counters().dropped, 0u);
	paced.stop();

	realTime.speed = -1;
	OpenNi2Source backwards(oni.string(), realTime);
	Status st = backwards.open();
	ASSERT_FALSE(st.ok());
	EXPECT_NE(std::string(st.error().message.view()).find("playback speed must be > 0"), std::string::npos)
		<< st.error().message.view();
}

TEST_F(OpenNi2RoundTrip, IhfRecordConvertsOniToRecBitIdentical)
{
	const fs::path oni = dir_ / "capture.oni";
	recordToOni(rec_, oni, stream_);
	// The ihf binary has no RUNPATH of its own: point it at the private copy.
	setenv("LD_LIBRARY_PATH", IHF_OPENNI2_ENV, 1);
	const fs::path out = dir_ / "back.rec";
	CommandResult r = runIhf("record --source openni2:" + oni.string() + " --out " + out.string());
	unsetenv("LD_LIBRARY_PATH");
	ASSERT_EQ(r.exitCode, 0) << r.output;

	auto reader = RecordingReader::open(out);
	ASSERT_TRUE(reader.ok()) << reader.error().message;
	ASSERT_EQ(reader->frameCount(), stream_.frames.size());
	EXPECT_NE(reader->header().sensorId.find("OpenNI2"), std::string::npos);
	DepthImage16 depth(kW, kH);
	for (size_t i = 0; i < reader->frameCount(); ++i) {
		recording::FrameRecord rec;
		ASSERT_EQ(*reader->read(i, rec, depth.view()), FrameCheck::kOk);
		EXPECT_EQ(rec.index, stream_.indices[i]);
		EXPECT_TRUE(sameDepth(depth.view(), stream_.frames[i])) << "frame " << i;
	}
}

TEST_F(OpenNi2RoundTrip, LiveDeviceDeliversFramesThenTimesOut)
{
	auto made = makeFrameSource("openni2:ihfrec:" + rec_.string());
	ASSERT_TRUE(made.ok());
	FrameSource &src = **made;
	Status opened = src.open();
	ASSERT_TRUE(opened.ok()) << opened.error().message;
	EXPECT_TRUE(src.info().live);
	EXPECT_NE(src.info().sensorId.find("ihf recording"), std::string::npos) << src.info().sensorId;
	ASSERT_TRUE(src.start().ok());

	// A live stream may skip frames under load; each one delivered must be
	// the recorded frame with its index, and the last one must arrive.
	Frame f;
	uint64_t last = 0;
	int got = 0;
	while (last < stream_.indices.back()) {
		auto r = src.next(f, 2s);
		ASSERT_TRUE(r.ok()) << r.error().message;
		ASSERT_EQ(*r, FrameOutcome::kFrame) << "no frame within 2 s after index " << last;
		ASSERT_GT(f.index, last);
		last = f.index;
		EXPECT_TRUE(sameDepth(f.depth, stream_.frames[f.index - 1])) << "frame " << f.index;
		++got;
	}
	EXPECT_EQ(src.counters().delivered + src.counters().dropped, stream_.frames.size());
	// The device has no more frames: a device never ends, it times out.
	auto r = src.next(f, 100ms);
	ASSERT_TRUE(r.ok());
	EXPECT_EQ(*r, FrameOutcome::kTimeout);
	EXPECT_EQ(src.counters().timeouts, 1u);
	src.stop();
}

TEST_F(OpenNi2RoundTrip, MissingDeviceAndFileAreClearErrors)
{
	OpenNi2Source missing((dir_ / "absent.oni").string());
	Status s = missing.open();
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("absent.oni"), std::string::npos) << s.error().message;

	auto bad = makeFrameSource("v4l3:/dev/video0");
	ASSERT_FALSE(bad.ok());
	EXPECT_NE(bad.error().message.find("unknown scheme 'v4l3'"), std::string::npos);
}

} // namespace
} // namespace ihf::test
