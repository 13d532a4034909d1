// SPDX-License-Identifier: MIT
// Writers replace files atomically: a failed write leaves the old file as it
// was and no temporary file behind.

#include <csignal>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

#include <sys/resource.h>
#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_io.h"
#include "tests/common/test_paths.h"
#include "tests/dataset/dataset_test_util.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

TEST(AtomicWrite, CreatesParentsAndLeavesNoTemp)
{
	auto dir = test::freshTempDir("atomic_ok");
	const fs::path file = dir / "a" / "b" / "results.csv";
	ASSERT_TRUE(writeResultsCsv(file, {}));
	EXPECT_EQ(test::readText(file), "scene_id,im_id,obj_id,score,R,t,time\n");
	ASSERT_TRUE(writeFileAtomic(file, std::string_view("replaced\n")));
	EXPECT_EQ(test::readText(file), "replaced\n");
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

TEST(AtomicWrite, ParentIsAFile)
{
	auto dir = test::freshTempDir("atomic_parent_file");
	test::writeText(dir / "blocker", "keep");
	const fs::path file = dir / "blocker" / "scene_gt.json";
	auto r = writeSceneGt(file, {});
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().code, Errc::kIo);
	EXPECT_NE(r.error().message.find(file.string()), std::string::npos) << r.error().message;
	EXPECT_EQ(test::readText(dir / "blocker"), "keep");
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

TEST(AtomicWrite, TargetIsADirectory)
{
	auto dir = test::freshTempDir("atomic_target_dir");
	fs::create_directories(dir / "out.png" / "inside");
	DepthImage16 img(4, 4, 7);
	auto r = writeDepthPng(dir / "out.png", img);
	ASSERT_FALSE(r);
	EXPECT_NE(r.error().message.find((dir / "out.png").string()), std::string::npos);
	EXPECT_TRUE(fs::is_directory(dir / "out.png" / "inside"));
	EXPECT_TRUE(test::tempLeftovers(dir).empty());

	auto e = writeDepthPng(dir / "empty.png", DepthImage16());
	ASSERT_FALSE(e);
	EXPECT_EQ(e.error().code, Errc::kInvalidArgument);
	EXPECT_FALSE(fs::exists(dir / "empty.png"));
}

// A FIFO (as /dev/null or /dev/stdout) is written in place: a rename over
// it would replace the device by a regular file.
TEST(AtomicWrite, AFifoIsWrittenInPlace)
{
	auto dir = test::freshTempDir("atomic_fifo");
	const fs::path fifo = dir / "out.csv";
	ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
	std::string got;
	std::thread reader([&] {
		std::ifstream in(fifo, std::ios::binary);
		got.assign(std::istreambuf_iterator<char>(in), {});
	});
	const Status written = writeResultsCsv(fifo, {});
	reader.join();
	ASSERT_TRUE(written) << written.error().message;
	EXPECT_EQ(got, "scene_id,im_id,obj_id,score,R,t,time\n");
	EXPECT_TRUE(fs::is_fifo(fifo));
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

TEST(AtomicWrite, FailedFillKeepsOldFile)
{
	auto dir = test::freshTempDir("atomic_fill_fails");
	const fs::path file = dir / "camera.json";
	test::writeText(file, "good\n");
	auto r = writeFileAtomic(file, [&](std::FILE *f) -> Status {
		std::fputs("half a fi", f);
		return makeError(Errc::kIo, file.string() + ": simulated failure");
	});
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().message, file.string() + ": simulated failure");
	EXPECT_EQ(test::readText(file), "good\n");
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

TEST(AtomicWrite, FailedJsonValueKeepsOldFile)
{
	auto dir = test::freshTempDir("atomic_nan");
	const fs::path file = dir / "scene_gt.json";
	std::map<int, std::vector<GtInstance>> gt;
	gt[3].push_back({5, Pose{}});
	ASSERT_TRUE(writeSceneGt(file, gt));
	const std::string before = test::readText(file);

	gt[3][0].pose.t.y() = std::nan("");
	auto r = writeSceneGt(file, gt);
	ASSERT_FALSE(r);
	EXPECT_NE(r.error().message.find(R"("3"[0].cam_t_m2c[1]: cannot write non-finite number)"),
		  std::string::npos)
		<< r.error().message;
	EXPECT_EQ(test::readText(file), before);
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

// Restores the file size limit and SIGXFSZ disposition however the test ends.
class FileSizeLimit
{
public:
	explicit FileSizeLimit(rlim_t bytes)
	{
		getrlimit(RLIMIT_FSIZE, &old_);
		oldHandler_ = std::signal(SIGXFSZ, SIG_IGN);
		rlimit lim = old_;
		lim.rlim_cur = bytes;
		ok_ = setrlimit(RLIMIT_FSIZE, &lim) == 0;
	}
	~FileSizeLimit()
	{
		setrlimit(RLIMIT_FSIZE, &old_);
		std::signal(SIGXFSZ, oldHandler_);
	}
	bool ok() const { return ok_; }

private:
	rlimit old_{};
	void (*oldHandler_)(int) = nullptr;
	bool ok_ = false;
};

// A real write failure in the middle of a PNG (the file system refuses bytes
// past a size limit): the good frame stays, nothing half-written remains.
TEST(AtomicWrite, DiskRefusesBytesKeepsOldFile)
{
	auto dir = test::freshTempDir("atomic_fsize");
	const fs::path file = dir / "000001.png";
	DepthImage16 good(16, 16, 1234);
	ASSERT_TRUE(writeDepthPng(file, good));

	std::mt19937 rng(7);
	DepthImage16 noise(640, 480); // incompressible: far above the limit
	for (uint16_t &v : noise.pixels())
		v = static_cast<uint16_t>(rng());

	Status r;
	{
		FileSizeLimit limit(8192);
		ASSERT_TRUE(limit.ok());
		r = writeDepthPng(file, noise);
	}
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().code, Errc::kIo);
	EXPECT_NE(r.error().message.find(file.string()), std::string::npos) << r.error().message;

	auto back = readDepthPng(file);
	ASSERT_TRUE(back) << back.error().message;
	EXPECT_EQ(back->width(), 16);
	EXPECT_EQ(back->at(5, 5), 1234);
	EXPECT_TRUE(test::tempLeftovers(dir).empty());
}

} // namespace
} // namespace ihf
