// SPDX-License-Identifier: MIT
// The .rec format: round trips, seeking, damage handling and pacing.

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "drivers/recording_reader.h"
#include "drivers/recording_source.h"
#include "drivers/replay_pacer.h"
#include "drivers/source_factory.h"
#include "tests/common/test_paths.h"
#include "tests/drivers/recording_test_util.h"

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// Plays a whole file in step mode; returns the frames' indices and checks
// every delivered frame against the stream it came from.
std::vector<uint64_t> playAll(RecordingSource &src, const TestStream &s)
{
	std::vector<uint64_t> got;
	Frame f;
	for (;;) {
		auto r = src.next(f, 0ns);
		EXPECT_TRUE(r.ok()) << r.error().message;
		if (!r.ok() || *r == FrameOutcome::kEndOfStream)
			break;
		EXPECT_EQ(*r, FrameOutcome::kFrame);
		auto it = std::find(s.indices.begin(), s.indices.end(), f.index);
		EXPECT_NE(it, s.indices.end());
		if (it == s.indices.end())
			break;
		const size_t i = static_cast<size_t>(it - s.indices.begin());
		EXPECT_TRUE(sameDepth(f.depth, s.frames[i])) << "frame " << f.index;
		EXPECT_EQ(f.deviceTimestampNs, s.deviceNs[i]);
		EXPECT_EQ(f.hostTimestampNs, s.hostNs[i]);
		got.push_back(f.index);
	}
	return got;
}

class RecordingRoundTrip : public ::testing::TestWithParam<bool>
{
};

TEST_P(RecordingRoundTrip, FramesAndHeaderAreBitIdentical)
{
	const bool compress = GetParam();
	const fs::path dir = freshTempDir(compress ? "rec_roundtrip_z" : "rec_roundtrip_raw");
	const fs::path file = dir / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, compress);

	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok()) << reader.error().message;
	EXPECT_TRUE(reader->indexed());
	EXPECT_EQ(reader->frameCount(), 5u);
	const auto want = testHeader();
	EXPECT_EQ(reader->header().sensorId, want.sensorId);
	EXPECT_EQ(reader->header().intrinsics.fx, want.intrinsics.fx);
	EXPECT_EQ(reader->header().intrinsics.fy, want.intrinsics.fy);
	EXPECT_EQ(reader->header().intrinsics.cx, want.intrinsics.cx);
	EXPECT_EQ(reader->header().intrinsics.cy, want.intrinsics.cy);
	EXPECT_EQ(reader->header().intrinsics.width, 64);
	EXPECT_EQ(reader->header().intrinsics.height, 48);
	EXPECT_EQ(reader->header().depthScale, 0.1);

	// The stored encoding is the one asked for (the test frames compress).
	DepthImage16 out(64, 48);
	recording::FrameRecord rec;
	ASSERT_EQ(*reader->read(0, rec, out.view()), FrameCheck::kOk);
	EXPECT_EQ(rec.encoding, compress ? recording::Encoding::kZlib : recording::Encoding::kRaw);
	if (!compress) { // header + 5 records + index + footer, exactly
		EXPECT_EQ(reader->fileSize(), recording::kHeaderFixedSize + want.sensorId.size() + 4 +
						      5 * (40 + 64 * 48 * 2) + 8 + 5 * 16 + 16);
	}

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	EXPECT_EQ(src.info().sensorId, want.sensorId);
	EXPECT_EQ(src.info().uri, "recording:" + file.string());
	EXPECT_FALSE(src.info().live);
	ASSERT_TRUE(src.start().ok());
	EXPECT_EQ(playAll(src, s), s.indices);
	EXPECT_EQ(src.counters().delivered, 5u);
	EXPECT_EQ(src.counters().corrupt, 0u);
	EXPECT_EQ(src.counters().dropped, 1u); // 13 is missing

	// The end stays the end.
	Frame f;
	EXPECT_EQ(*src.next(f, 0ns), FrameOutcome::kEndOfStream);
}

INSTANTIATE_TEST_SUITE_P(RawAndZlib, RecordingRoundTrip, ::testing::Values(false, true));

TEST(RecordingSeek, ByFrameIndex)
{
	const fs::path file = freshTempDir("rec_seek") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, true);

	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->find(14), std::optional<size_t>(3));
	EXPECT_EQ(reader->find(10), std::optional<size_t>(0));
	EXPECT_FALSE(reader->find(13).has_value());
	EXPECT_FALSE(reader->find(99).has_value());

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	ASSERT_TRUE(src.seek(14).ok());
	Frame f;
	ASSERT_EQ(*src.next(f, 0ns), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 14u);
	EXPECT_TRUE(sameDepth(f.depth, s.frames[3]));
	ASSERT_TRUE(src.seek(11).ok()); // backwards too
	ASSERT_EQ(*src.next(f, 0ns), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 11u);
	EXPECT_TRUE(sameDepth(f.depth, s.frames[1]));

	Status missing = src.seek(13);
	ASSERT_FALSE(missing.ok());
	EXPECT_EQ(missing.error().code, Errc::kNotFound);
	EXPECT_NE(missing.error().message.find("13"), std::string::npos);
}

// Flips one payload byte of the frame at position pos.
void corruptPayload(const fs::path &file, size_t pos, size_t byteInPayload)
{
	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	const uint64_t at = reader->entry(pos).offset + recording::kFrameHeaderSize + byteInPayload;
	std::vector<uint8_t> bytes = readBytes(file);
	ASSERT_LT(at, bytes.size());
	bytes[at] ^= 0x5a;
	writeBytes(file, bytes);
}

TEST_P(RecordingRoundTrip, CorruptFrameIsSkippedAndCounted)
{
	const bool compress = GetParam();
	const fs::path file = freshTempDir(compress ? "rec_crc_z" : "rec_crc_raw") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, compress);
	corruptPayload(file, 1, 20);

	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	DepthImage16 out(64, 48);
	recording::FrameRecord rec;
	const char *why = nullptr;
	ASSERT_EQ(*reader->read(1, rec, out.view(), &why), FrameCheck::kCorrupt);
	EXPECT_STREQ(why, "CRC32 mismatch");

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	EXPECT_EQ(playAll(src, s), (std::vector<uint64_t>{10, 12, 14, 15}));
	EXPECT_EQ(src.counters().corrupt, 1u);
	EXPECT_EQ(src.counters().delivered, 4u);
	EXPECT_EQ(src.counters().dropped, 1u); // 13; the corrupt 11 is counted once, as corrupt
}

TEST(RecordingDamage, CorruptFrameHeaderIsSkippedToo)
{
	const fs::path file = freshTempDir("rec_crc_head") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, false);
	// Byte 20 of the record is inside the device timestamp.
	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	std::vector<uint8_t> bytes = readBytes(file);
	bytes[reader->entry(2).offset + 20] ^= 1;
	writeBytes(file, bytes);

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	EXPECT_EQ(playAll(src, s), (std::vector<uint64_t>{10, 11, 14, 15}));
	EXPECT_EQ(src.counters().corrupt, 1u);
}

// Looped, each pass adds the index span (15 - 10 + 1) to the indices and as
// many recorded frame intervals (33.33 ms) to the timestamps; the corrupt
// frame is skipped and counted on every pass, and is not a gap.
TEST(RecordingLoop, IndicesAndTimestampsRunOnAcrossPasses)
{
	const fs::path file = freshTempDir("rec_loop") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, true);
	corruptPayload(file, 1, 20);

	RecordingSourceOptions o;
	o.loop = true;
	RecordingSource src(file, o);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	const int64_t passNs = 6 * 33'333'333;
	const std::vector<size_t> good = {0, 2, 3, 4};
	Frame f;
	for (uint64_t pass = 0; pass < 3; ++pass) {
		for (size_t i : good) {
			auto r = src.next(f, 0ns);
			ASSERT_TRUE(r.ok()) << r.error().message;
			ASSERT_EQ(*r, FrameOutcome::kFrame);
			EXPECT_EQ(f.index, s.indices[i] + 6 * pass);
			EXPECT_EQ(f.hostTimestampNs, s.hostNs[i] + static_cast<int64_t>(pass) * passNs);
			EXPECT_EQ(f.deviceTimestampNs, s.deviceNs[i] + static_cast<int64_t>(pass) * passNs);
			EXPECT_TRUE(sameDepth(f.depth, s.frames[i])) << "frame " << f.index;
		}
		EXPECT_EQ(src.pass(), pass + 1);
	}
	EXPECT_EQ(src.counters().delivered, 12u);
	EXPECT_EQ(src.counters().corrupt, 3u);
	EXPECT_EQ(src.counters().dropped, 3u); // 13, 19 and 25: index 13 of each pass

	// Reopening starts again at the first pass.
	src.stop();
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	ASSERT_EQ(*src.next(f, 0ns), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 10u);
	EXPECT_EQ(src.pass(), 1u);
}

TEST(RecordingLoop, APassWithoutAGoodFrameEndsTheStream)
{
	const fs::path file = freshTempDir("rec_loop_bad") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, false);
	for (size_t pos = 0; pos < s.indices.size(); ++pos)
		corruptPayload(file, pos, 7);

	RecordingSourceOptions o;
	o.loop = true;
	RecordingSource src(file, o);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	Frame f;
	auto r = src.next(f, 0ns);
	ASSERT_TRUE(r.ok());
	EXPECT_EQ(*r, FrameOutcome::kEndOfStream);
	EXPECT_EQ(src.counters().corrupt, 5u);
	EXPECT_EQ(src.counters().delivered, 0u);
}

TEST(RecordingLoop, TheUriSaysLoopOrNot)
{
	const fs::path file = freshTempDir("rec_loop_uri") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, false);
	for (const char *query : {"?loop=1", "?loop=0", ""}) {
		const std::string uri = "recording:" + file.string() + query;
		auto made = makeFrameSource(uri);
		ASSERT_TRUE(made.ok()) << made.error().message;
		FrameSource &src = **made;
		EXPECT_EQ(src.info().uri, uri);
		ASSERT_TRUE(src.open().ok());
		ASSERT_TRUE(src.start().ok());
		Frame f;
		std::vector<uint64_t> got;
		for (int i = 0; i < 7; ++i) {
			auto r = src.next(f, 0ns);
			ASSERT_TRUE(r.ok());
			if (*r != FrameOutcome::kFrame)
				break;
			got.push_back(f.index);
		}
		if (std::string(query) == "?loop=1")
			EXPECT_EQ(got, (std::vector<uint64_t>{10, 11, 12, 14, 15, 16, 17}));
		else
			EXPECT_EQ(got, s.indices);
	}
	auto bad = makeFrameSource("recording:" + file.string() + "?loop=yes");
	ASSERT_FALSE(bad.ok());
	EXPECT_NE(bad.error().message.find("?loop=1"), std::string::npos) << bad.error().message;
	EXPECT_FALSE(makeFrameSource("recording:?loop=1").ok());
}

TEST(RecordingDamage, TruncatedFileEndsCleanlyAfterTheCompleteFrames)
{
	const fs::path dir = freshTempDir("rec_trunc");
	const fs::path file = dir / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, false);
	std::vector<uint64_t> offsets;
	{
		auto reader = RecordingReader::open(file);
		ASSERT_TRUE(reader.ok());
		for (size_t i = 0; i < reader->frameCount(); ++i)
			offsets.push_back(reader->entry(i).offset);
	}
	const std::vector<uint8_t> full = readBytes(file);

	// Cut inside frame 3's payload: frames 0..2 are complete.
	writeBytes(file, std::vector<uint8_t>(full.begin(), full.begin() + static_cast<long>(offsets[3] + 40 + 1000)));
	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok()) << reader.error().message;
	EXPECT_FALSE(reader->indexed());
	EXPECT_NE(reader->indexNote().find("truncated"), std::string::npos) << reader->indexNote();
	EXPECT_EQ(reader->frameCount(), 3u);
	EXPECT_EQ(reader->tailBytes(), 40u + 1000u);

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	EXPECT_EQ(playAll(src, s), (std::vector<uint64_t>{10, 11, 12}));
	EXPECT_EQ(src.counters().corrupt, 0u);

	// Cut inside a record header, and right after the last record (a writer
	// that died before the index): scanning finds exactly the complete ones.
	writeBytes(file, std::vector<uint8_t>(full.begin(), full.begin() + static_cast<long>(offsets[2] + 17)));
	reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->frameCount(), 2u);
	const size_t recordsEnd = offsets[4] + 40 + 64 * 48 * 2;
	writeBytes(file, std::vector<uint8_t>(full.begin(), full.begin() + static_cast<long>(recordsEnd)));
	reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->frameCount(), 5u);
	EXPECT_EQ(reader->tailBytes(), 0u);
	// Only the header: a valid, empty stream.
	writeBytes(file, std::vector<uint8_t>(full.begin(), full.begin() + static_cast<long>(offsets[0])));
	RecordingSource empty(file);
	ASSERT_TRUE(empty.open().ok());
	ASSERT_TRUE(empty.start().ok());
	Frame f;
	EXPECT_EQ(*empty.next(f, 0ns), FrameOutcome::kEndOfStream);
}

TEST(RecordingDamage, DamagedIndexFallsBackToScanning)
{
	const fs::path file = freshTempDir("rec_badindex") / "s.rec";
	const TestStream s = testStream();
	writeStream(file, s, true);
	std::vector<uint8_t> bytes = readBytes(file);
	bytes[bytes.size() - 16 - 5] ^= 0xff; // inside the last index entry
	writeBytes(file, bytes);

	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	EXPECT_FALSE(reader->indexed());
	EXPECT_EQ(reader->indexNote(), "index CRC mismatch");
	EXPECT_EQ(reader->frameCount(), 5u);
	EXPECT_EQ(reader->find(15), std::optional<size_t>(4));

	RecordingSource src(file);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	EXPECT_EQ(playAll(src, s), s.indices);
}

// Opening must fail with an error naming the file and the header field.
void expectHeaderError(const fs::path &file, Errc code, const std::string &field)
{
	auto reader = RecordingReader::open(file);
	ASSERT_FALSE(reader.ok());
	EXPECT_EQ(reader.error().code, code) << reader.error().message;
	EXPECT_NE(reader.error().message.find(file.string()), std::string::npos) << reader.error().message;
	EXPECT_NE(reader.error().message.find("'" + field + "'"), std::string::npos) << reader.error().message;
	RecordingSource src(file);
	Status st = src.open();
	ASSERT_FALSE(st.ok());
	EXPECT_EQ(st.error().message, reader.error().message);
}

TEST(RecordingBadHeader, WrongMagicVersionTruncationAndCrc)
{
	const fs::path dir = freshTempDir("rec_badheader");
	const fs::path good = dir / "good.rec";
	writeStream(good, testStream(), false);
	const std::vector<uint8_t> full = readBytes(good);

	std::vector<uint8_t> b = full;
	b[3] = 'X';
	writeBytes(dir / "magic.rec", b);
	expectHeaderError(dir / "magic.rec", Errc::kParse, "magic");

	b = full;
	b[8] = 2; // version 2
	writeBytes(dir / "version.rec", b);
	expectHeaderError(dir / "version.rec", Errc::kUnsupported, "version");
	auto v = RecordingReader::open(dir / "version.rec");
	EXPECT_NE(v.error().message.find("version 2 is not supported"), std::string::npos);

	writeBytes(dir / "short.rec", std::vector<uint8_t>(full.begin(), full.begin() + 30));
	expectHeaderError(dir / "short.rec", Errc::kCorrupt, "sensor_id_size");
	writeBytes(dir / "shorter.rec", std::vector<uint8_t>(full.begin(), full.begin() + 5));
	expectHeaderError(dir / "shorter.rec", Errc::kCorrupt, "magic");
	writeBytes(dir / "noid.rec", std::vector<uint8_t>(full.begin(), full.begin() + 70));
	expectHeaderError(dir / "noid.rec", Errc::kCorrupt, "header_crc");

	b = full;
	b[25] ^= 1; // inside fx
	writeBytes(dir / "crc.rec", b);
	expectHeaderError(dir / "crc.rec", Errc::kCorrupt, "header_crc");

	auto missing = RecordingReader::open(dir / "absent.rec");
	ASSERT_FALSE(missing.ok());
	EXPECT_EQ(missing.error().code, Errc::kNotFound);
}

// A device or FIFO cannot take a recording (its index is written last, and
// a rename over it would replace the device): a clear error, nothing made.
TEST(RecordingWriter, RefusesADeviceOrFifo)
{
	const fs::path dir = freshTempDir("rec_fifo");
	const fs::path fifo = dir / "out.rec";
	ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
	auto w = RecordingWriter::create(fifo, testHeader());
	ASSERT_FALSE(w.ok());
	EXPECT_EQ(w.error().code, Errc::kInvalidArgument);
	EXPECT_NE(w.error().message.find("not a regular file"), std::string::npos) << w.error().message;
	EXPECT_TRUE(fs::is_fifo(fifo));
	EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(RecordingWriter, IsAtomicAndValidatesFrames)
{
	const fs::path dir = freshTempDir("rec_writer");
	const fs::path file = dir / "out.rec";
	const TestStream s = testStream();
	{
		auto w = RecordingWriter::create(file, testHeader());
		ASSERT_TRUE(w.ok());
		ASSERT_TRUE(w->append({1, 0, 0}, s.frames[0].view()).ok());
		EXPECT_FALSE(fs::exists(file)); // only the temporary exists so far

		Status again = w->append({1, 0, 0}, s.frames[0].view());
		ASSERT_FALSE(again.ok());
		EXPECT_NE(again.error().message.find("does not follow"), std::string::npos);
		DepthImage16 wrong(10, 10);
		Status size = w->append({2, 0, 0}, wrong.view());
		ASSERT_FALSE(size.ok());
		EXPECT_NE(size.error().message.find("10x10"), std::string::npos);
		// Dropped without finish(): no target, no leftovers.
	}
	EXPECT_FALSE(fs::exists(file));
	EXPECT_TRUE(fs::is_empty(dir));

	// A finished file replaces an older one whole.
	writeBytes(file, {1, 2, 3});
	writeStream(file, s, false);
	auto reader = RecordingReader::open(file);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->frameCount(), 5u);
	EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

// Simulated time: sleeping moves "now" forward; every sleep is logged.
class FakeClock : public PacingClock
{
public:
	int64_t nowNs() override { return now; }
	void sleepUntil(int64_t deadlineNs) override
	{
		sleeps.push_back(deadlineNs);
		now = std::max(now, deadlineNs);
	}

	int64_t now = 1'000'000;
	std::vector<int64_t> sleeps;
};

// The pacer both file sources and ihf run's loop use: anchored by the first
// frame after a reset, later frames due by their recorded time / speed.
TEST(ReplayPacer, AnchorsOnTheFirstFrameAndScalesBySpeed)
{
	FakeClock clock;
	ReplayPacer pacer(clock, 2.0);
	EXPECT_EQ(pacer.due(7'000'000'000), clock.now); // anchors
	EXPECT_EQ(pacer.due(7'100'000'000), clock.now + 50'000'000);
	EXPECT_EQ(pacer.due(6'900'000'000), clock.now - 50'000'000); // an earlier stamp was due earlier

	// Not due within the timeout: sleeps the timeout, the frame stays.
	EXPECT_FALSE(pacer.waitFor(7'200'000'000, std::chrono::milliseconds(10)));
	EXPECT_EQ(clock.now, 1'000'000 + 10'000'000);
	EXPECT_TRUE(pacer.waitFor(7'200'000'000, std::chrono::milliseconds(200)));
	EXPECT_EQ(clock.now, 1'000'000 + 100'000'000);
	EXPECT_TRUE(pacer.waitFor(7'000'000'000, std::chrono::milliseconds(0))); // late: at once
	EXPECT_EQ(clock.now, 1'000'000 + 100'000'000);

	pacer.reset(); // the next frame anchors anew
	EXPECT_EQ(pacer.due(9'000'000'000), clock.now);

	EXPECT_TRUE(ReplayPacer::validSpeed(0.5));
	for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL})
		EXPECT_FALSE(ReplayPacer::validSpeed(bad)) << bad;
}

TEST(RecordingPacing, ASpeedThatCannotPaceIsRefusedAtOpen)
{
	const fs::path file = freshTempDir("rec_bad_speed") / "s.rec";
	writeStream(file, testStream(), false);
	RecordingSourceOptions o;
	o.pacing = Pacing::kRealTime;
	o.speed = 0;
	RecordingSource src(file, o);
	Status st = src.open();
	ASSERT_FALSE(st.ok());
	EXPECT_NE(std::string(st.error().message.view()).find("playback speed must be > 0"), std::string::npos)
		<< st.error().message.view();
	o.pacing = Pacing::kStep; // a step never divides by it
	EXPECT_TRUE(RecordingSource(file, o).open().ok());
}

TEST(RecordingPacing, RealTimeFollowsHostTimestampsOnTheInjectedClock)
{
	const fs::path file = freshTempDir("rec_pacing") / "s.rec";
	TestStream s = testStream();
	s.hostNs = {0, 33'000'000, 66'000'000, 200'000'000, 210'000'000};
	writeStream(file, s, false);

	FakeClock clock;
	RecordingSourceOptions o;
	o.pacing = Pacing::kRealTime;
	o.clock = &clock;
	RecordingSource src(file, o);
	ASSERT_TRUE(src.open().ok());
	ASSERT_TRUE(src.start().ok());
	const int64_t t0 = clock.now;
	Frame f;

	ASSERT_EQ(*src.next(f, 1s), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 10u);
	EXPECT_EQ(clock.now, t0);
	ASSERT_EQ(*src.next(f, 1s), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 11u);
	EXPECT_EQ(clock.now, t0 + 33'000'000);
	ASSERT_EQ(*src.next(f, 1s), FrameOutcome::kFrame);
	EXPECT_EQ(clock.now, t0 + 66'000'000);

	// Frame 14 is due at +200 ms: a 50 ms wait times out at +116 ms...
	ASSERT_EQ(*src.next(f, 50ms), FrameOutcome::kTimeout);
	EXPECT_EQ(clock.now, t0 + 116'000'000);
	EXPECT_EQ(src.counters().timeouts, 1u);
	// ...and the frame is still the next one, delivered on time.
	ASSERT_EQ(*src.next(f, 100ms), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 14u);
	EXPECT_EQ(clock.now, t0 + 200'000'000);
	EXPECT_TRUE(sameDepth(f.depth, s.frames[3]));

	// A consumer that falls behind gets the frame at once, no sleep into the past.
	clock.now = t0 + 500'000'000;
	ASSERT_EQ(*src.next(f, 0ns), FrameOutcome::kFrame);
	EXPECT_EQ(f.index, 15u);
	EXPECT_EQ(clock.now, t0 + 500'000'000);
	EXPECT_EQ(*src.next(f, 1s), FrameOutcome::kEndOfStream);
}

TEST(RecordingPacing, SpeedScalesAndStepModeNeverSleeps)
{
	const fs::path file = freshTempDir("rec_speed") / "s.rec";
	TestStream s = testStream();
	s.hostNs = {0, 40'000'000, 80'000'000, 120'000'000, 160'000'000};
	writeStream(file, s, false);

	FakeClock clock;
	RecordingSourceOptions o;
	o.pacing = Pacing::kRealTime;
	o.speed = 2.0;
	o.clock = &clock;
	RecordingSource fast(file, o);
	ASSERT_TRUE(fast.open().ok());
	ASSERT_TRUE(fast.start().ok());
	const int64_t t0 = clock.now;
	Frame f;
	for (int i = 0; i < 5; ++i) {
		ASSERT_EQ(*fast.next(f, 1s), FrameOutcome::kFrame);
		EXPECT_EQ(clock.now, t0 + i * 20'000'000);
	}

	FakeClock idle;
	o.pacing = Pacing::kStep;
	o.clock = &idle;
	RecordingSource step(file, o);
	ASSERT_TRUE(step.open().ok());
	ASSERT_TRUE(step.start().ok());
	for (int i = 0; i < 5; ++i)
		ASSERT_EQ(*step.next(f, 0ns), FrameOutcome::kFrame);
	EXPECT_TRUE(idle.sleeps.empty());
}

TEST(RecordingSource, CallsOutOfOrderAreErrors)
{
	const fs::path file = freshTempDir("rec_order") / "s.rec";
	writeStream(file, testStream(), false);
	RecordingSource src(file);
	Frame f;
	EXPECT_FALSE(src.start().ok());
	ASSERT_TRUE(src.open().ok());
	auto r = src.next(f, 0ns);
	ASSERT_FALSE(r.ok());
	EXPECT_NE(r.error().message.find("before start"), std::string::npos);
}

} // namespace
} // namespace ihf::test
