// SPDX-License-Identifier: MIT
// `ihf run` end to end on a replayed recording: a small synthetic bunny
// dataset (ihf synth), a tiny forest (ihf train), the dataset recorded with
// its boxes (ihf record --from-bop --boxes-out); `ihf run` must give exactly
// the poses `ihf estimate` gives on the same frames and boxes. Then the bad
// inputs: a box for an unknown object (an error line, the other boxes go
// on), a corrupt frame (skipped and counted, the stream goes on), a
// truncated recording (ends cleanly), SIGTERM (clean stop, output complete).

#include <csignal>
#include <fstream>
#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/file.h>
#include <unistd.h>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <png.h>
#include <nlohmann/json.hpp>

#include "core/dataset/bop_io.h"
#include "drivers/recording_reader.h"
#include "tests/common/test_paths.h"

extern char **environ;

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct PoseKey {
	int frame;
	int obj;
	bool operator<(const PoseKey &o) const { return std::tie(frame, obj) < std::tie(o.frame, o.obj); }
};

struct RunOutput {
	std::map<PoseKey, json> poses;
	std::vector<json> errors;
};

RunOutput readRunOutput(const fs::path &file)
{
	RunOutput out;
	std::ifstream in(file);
	std::string line;
	while (std::getline(in, line)) {
		json j = json::parse(line);
		if (j.contains("error"))
			out.errors.push_back(j);
		else
			out.poses[{j["frame"].get<int>(), j["obj_id"].get<int>()}] = j;
	}
	return out;
}

const auto q = test::quoted; // a path in single quotes, for the shell

// `ihf estimate` on the data's dataset and forest with the bundled config.
std::string estimateCommand(const fs::path &d, const fs::path &out, const std::string &extra = "")
{
	return "estimate --dataset " + q(d / "ds") + " --boxes " + q(d / "ds" / "boxes.json") + " --forest 20=" +
	       q(d / "bunny.ihf") + " --config " + q(sourceDir() / "config" / "estimate.toml") + " " + extra +
	       " --out " + q(out);
}

class RunReplay : public ::testing::Test
{
protected:
	// The data (dataset, forest, recording, estimate's results) is made once
	// per ihf binary and shared by the test processes ctest starts, under a
	// lock so parallel ones wait instead of making it twice.
	static void SetUpTestSuite()
	{
		dir_ = new fs::path(fs::temp_directory_path() / "ihf_test_run_replay");
		fs::create_directories(*dir_);
		const int lock = ::open((*dir_ / ".lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
		ASSERT_GE(lock, 0);
		flock(lock, LOCK_EX);
		// The ihf binary and this test's build (it writes the configs).
		const std::string stamp = std::to_string(fs::last_write_time(ihfBinary()).time_since_epoch().count()) +
					  " " + std::to_string(fs::file_size(ihfBinary())) + " " + __DATE__ " " __TIME__;
		std::string ready;
		std::getline(std::ifstream(*dir_ / "ready"), ready);
		if (ready != stamp) {
			for (const auto &e : fs::directory_iterator(*dir_))
				if (e.path().filename() != ".lock")
					fs::remove_all(e.path());
			makeData();
			if (!HasFatalFailure())
				std::ofstream(*dir_ / "ready") << stamp << "\n";
		}
		flock(lock, LOCK_UN);
		::close(lock);
	}

	static void makeData()
	{
		const fs::path &d = *dir_;
		const fs::path models = sourceDir() / "config" / "models";
		CommandResult r = runIhf("synth --models " + q(models) + " --objects 20 --images 3 --seed 5 --out " +
					 q(d / "ds"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		std::ofstream(d / "train.toml") << "[views]\nviewpoints = 20\ninplane_steps = 2\n"
						   "[scales]\nfactors = [1.0]\nparts_per_image = 8\noccluded_views = 0.0\n"
					   "[parts]\nkind = \"variable\"\nmax_control_points = 256\n";
		r = runIhf("train --model " + q(models / "obj_000020.ply") + " --config " + q(d / "train.toml") +
			   " --out " + q(d / "bunny.ihf"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		r = runIhf("record --from-bop " + q(d / "ds") + " --compress --out " + q(d / "ds.rec") +
			   " --boxes " + q(d / "ds" / "boxes.json") + " --boxes-out " + q(d / "boxes.jsonl"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		r = runIhf(estimateCommand(d, d / "est.csv"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		// A short 30 Hz sequence of the bunny (ihf synth --sequence writes its
		// recording and box lines too), estimated as a stream.
		r = runIhf("synth --sequence --models " + q(models) + " --objects 20 --sequences 1 --frames 8 --seed 3 "
			   "--quiet --out " + q(d / "seq"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		r = runIhf("estimate --dataset " + q(d / "seq") + " --boxes " + q(d / "seq" / "boxes.json") +
			   " --forest 20=" + q(d / "bunny.ihf") + " --config " +
			   q(sourceDir() / "config" / "estimate.toml") + " --sequence --out " + q(d / "est_sequence.csv"));
		ASSERT_EQ(r.exitCode, 0) << r.output;

		// The same boxes, plus one for an object without a forest in the first frame.
		std::ifstream in(d / "boxes.jsonl");
		std::ofstream out(d / "boxes_unknown.jsonl");
		std::string line;
		bool first = true;
		while (std::getline(in, line)) {
			json j = json::parse(line);
			if (first)
				j["boxes"].insert(j["boxes"].begin(), json{{"obj_id", 99}, {"bbox", {100, 100, 50, 50}}});
			first = false;
			out << j.dump() << "\n";
		}
		out.close();
		// Every box a cold estimate, as ihf estimate without --sequence;
		// device_tracking.toml tracks, as ihf estimate --sequence.
		for (const bool tracking : {false, true})
			std::ofstream(d / (tracking ? "device_tracking.toml" : "device.toml"))
				<< "[source]\nuri = \"recording:" << (tracking ? "seq/recordings/000001.rec" : "ds.rec") << "\"\n"
				<< "[boxes]\ninput = \"file:"
				<< (tracking ? "seq/recordings/000001.boxes.jsonl" : "boxes_unknown.jsonl")
				<< "\"\ntimeout_ms = 20000\n"
				<< "[output]\nposes = \"file:" << (tracking ? "poses_tracking.jsonl" : "poses.jsonl") << "\"\n"
				<< "[objects]\n20 = \"bunny.ihf\"\n"
				<< "[estimate]\nconfig = \"" << (sourceDir() / "config" / "estimate.toml").string() << "\"\n"
				<< "[tracking]\nenabled = " << (tracking ? "true" : "false") << "\n"
				<< "[run]\nstats_interval_s = 0\n";
	}
	static void TearDownTestSuite() { delete dir_; }

	static fs::path *dir_;
};

fs::path *RunReplay::dir_ = nullptr;

// The rows of ihf estimate's CSV by (image id, object).
std::map<PoseKey, ResultRow> estimateRows(const fs::path &csv)
{
	auto rows = readResultsCsv(csv);
	EXPECT_TRUE(rows.ok());
	std::map<PoseKey, ResultRow> m;
	for (const ResultRow &r : *rows)
		m[{r.imId, r.objId}] = r;
	return m;
}

void expectSamePose(const json &j, const ResultRow &r)
{
	for (int i = 0; i < 9; ++i)
		EXPECT_EQ(j["R"][i].get<double>(), r.pose.R(i / 3, i % 3)) << j.dump();
	for (int i = 0; i < 3; ++i)
		EXPECT_EQ(j["t"][i].get<double>(), r.pose.t(i)) << j.dump();
	EXPECT_EQ(j["confidence"].get<double>(), r.score);
	EXPECT_GE(j["iterations"].get<int>(), 0);
	EXPECT_GE(j["latency_ms"].get<double>(), j["estimate_ms"].get<double>());
}

// Every pose `ihf estimate` wrote is in `ihf run`'s output, bit for bit, and
// no other.
void expectSamePoses(const RunOutput &got, const std::map<PoseKey, ResultRow> &expected, const std::string &output)
{
	ASSERT_EQ(got.poses.size(), expected.size()) << output;
	for (const auto &[key, row] : expected) {
		auto it = got.poses.find(key);
		ASSERT_NE(it, got.poses.end()) << "no pose for frame " << key.frame;
		expectSamePose(it->second, row);
	}
}

TEST_F(RunReplay, SamePosesAsEstimateAndAnErrorLineForAnUnknownObject)
{
	const fs::path &d = *dir_;
	CommandResult r = runIhf("run --config " + q(d / "device.toml"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("end of stream; frames 3 processed 3 late 0 corrupt 0"), std::string::npos)
		<< r.output;

	const auto expected = estimateRows(d / "est.csv");
	ASSERT_GE(expected.size(), 2u) << "the tiny forest should find most bunnies";
	const RunOutput got = readRunOutput(d / "poses.jsonl");
	ASSERT_NO_FATAL_FAILURE(expectSamePoses(got, expected, r.output));
	ASSERT_EQ(got.errors.size(), 1u);
	EXPECT_EQ(got.errors[0]["obj_id"], 99);
	EXPECT_EQ(got.errors[0]["error"], "no forest for object 99");
	EXPECT_EQ(got.errors[0]["frame"], expected.begin()->first.frame);
}

// With tracking, `ihf run` on a sequence's recording gives exactly the
// poses of `ihf estimate --sequence` on the sequence, and says how each was
// found.
TEST_F(RunReplay, TrackingGivesTheSamePosesAsEstimateSequence)
{
	const fs::path &d = *dir_;
	CommandResult r = runIhf("run --config " + q(d / "device_tracking.toml"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("tracking: tracked"), std::string::npos) << r.output;
	const auto expected = estimateRows(d / "est_sequence.csv");
	ASSERT_GE(expected.size(), 2u);
	const RunOutput got = readRunOutput(d / "poses_tracking.jsonl");
	ASSERT_NO_FATAL_FAILURE(expectSamePoses(got, expected, r.output));
	for (const auto &[key, j] : got.poses) {
		ASSERT_TRUE(j.contains("mode")) << j.dump();
		EXPECT_TRUE(j["mode"] == "track" || j["mode"] == "detect") << j.dump();
		EXPECT_GT(j["track_id"].get<int>(), 0);
	}
	// The first frame can only be detected; later ones are tracked.
	EXPECT_EQ(got.poses.begin()->second["mode"], "detect");
	EXPECT_TRUE(std::any_of(got.poses.begin(), got.poses.end(),
				[](const auto &p) { return p.second["mode"] == "track"; }))
		<< r.output;
}

// The kind of box reaches the estimator the same way in both commands: with
// modal boxes `ihf run` gives `ihf estimate --box-kind modal`'s poses, which
// differ from the amodal ones (the score's weights differ).
TEST_F(RunReplay, TheBoxKindGivesTheSamePosesAsEstimate)
{
	const fs::path &d = *dir_;
	CommandResult r = runIhf(estimateCommand(d, d / "est_modal.csv", "--box-kind modal"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto modal = estimateRows(d / "est_modal.csv");
	const auto amodal = estimateRows(d / "est.csv");
	ASSERT_EQ(modal.size(), amodal.size());
	bool differs = false;
	for (const auto &[key, row] : modal)
		differs = differs || row.score != amodal.at(key).score || !row.pose.t.isApprox(amodal.at(key).pose.t);
	EXPECT_TRUE(differs) << "the modal weights should change some confidence";

	r = runIhf("run --config " + q(d / "device.toml") + " --boxes file:" + q(d / "boxes.jsonl") +
		   " --box-kind modal --out file:" + q(d / "poses_modal.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const RunOutput got = readRunOutput(d / "poses_modal.jsonl");
	ASSERT_NO_FATAL_FAILURE(expectSamePoses(got, modal, r.output));

	r = runIhf("run --config " + q(d / "device.toml") + " --box-kind visible");
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.output.find("--box-kind"), std::string::npos) << r.output;
}

TEST_F(RunReplay, CorruptFrameIsSkippedAndCountedTheStreamGoesOn)
{
	const fs::path &d = *dir_;
	fs::copy_file(d / "ds.rec", d / "corrupt.rec", fs::copy_options::overwrite_existing);
	uint64_t badFrame = 0;
	{
		auto reader = RecordingReader::open(d / "corrupt.rec");
		ASSERT_TRUE(reader.ok());
		ASSERT_EQ(reader->frameCount(), 3u);
		badFrame = reader->entry(1).frameIndex;
		std::fstream f(d / "corrupt.rec", std::ios::in | std::ios::out | std::ios::binary);
		f.seekp(static_cast<std::streamoff>(reader->entry(1).offset + 40 + 20));
		char c = 0;
		f.read(&c, 1);
		f.seekp(static_cast<std::streamoff>(reader->entry(1).offset + 40 + 20));
		c ^= 0x5a;
		f.write(&c, 1);
	}
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --source recording:" +
				 q(d / "corrupt.rec") + " --out file:" + q(d / "corrupt.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("frames 2 processed 2 late 0 corrupt 1"), std::string::npos) << r.output;
	const auto expected = estimateRows(d / "est.csv");
	const RunOutput got = readRunOutput(d / "corrupt.jsonl");
	for (const auto &[key, row] : expected) {
		auto it = got.poses.find(key);
		if (key.frame == static_cast<int>(badFrame)) {
			EXPECT_EQ(it, got.poses.end());
			continue;
		}
		ASSERT_NE(it, got.poses.end());
		expectSamePose(it->second, row);
	}
}

TEST_F(RunReplay, TruncatedRecordingEndsCleanly)
{
	const fs::path &d = *dir_;
	uint64_t cut = 0, lastFrame = 0;
	{
		auto reader = RecordingReader::open(d / "ds.rec");
		ASSERT_TRUE(reader.ok());
		cut = reader->entry(2).offset + 100;
		lastFrame = reader->entry(2).frameIndex;
	}
	fs::copy_file(d / "ds.rec", d / "cut.rec", fs::copy_options::overwrite_existing);
	fs::resize_file(d / "cut.rec", cut);
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --source recording:" + q(d / "cut.rec") +
				 " --out file:" + q(d / "cut.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("end of stream; frames 2 processed 2"), std::string::npos) << r.output;
	const RunOutput got = readRunOutput(d / "cut.jsonl");
	for (const auto &[key, pose] : got.poses)
		EXPECT_NE(key.frame, static_cast<int>(lastFrame));
}

TEST_F(RunReplay, SigtermStopsCleanlyWithTheOutputComplete)
{
	const fs::path &d = *dir_;
	// Real time at 1/100 speed: frames 3.3 s apart, so the run is still going.
	const std::string cfg = (d / "device.toml").string();
	const std::string out = "file:" + (d / "sigterm.jsonl").string();
	const std::string err = (d / "sigterm.err").string();
	std::vector<std::string> args = {ihfBinary().string(), "run", "--config", cfg, "--out", out, "--real-time"};
	{
		// speed lives in [source]: a copy of the config with it set.
		std::ifstream in(cfg);
		std::string text((std::istreambuf_iterator<char>(in)), {});
		text.replace(text.find("[source]\n"), 9, "[source]\nspeed = 0.01\n");
		std::ofstream(d / "slow.toml") << text;
	}
	args[3] = (d / "slow.toml").string();
	std::vector<char *> argv;
	for (auto &a : args)
		argv.push_back(a.data());
	argv.push_back(nullptr);
	posix_spawn_file_actions_t fa;
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	pid_t pid = 0;
	ASSERT_EQ(posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ), 0);
	posix_spawn_file_actions_destroy(&fa);
	std::this_thread::sleep_for(std::chrono::milliseconds(1500));
	ASSERT_EQ(kill(pid, SIGTERM), 0);
	int status = 0;
	ASSERT_EQ(waitpid(pid, &status, 0), pid);
	std::ifstream in(err);
	const std::string text((std::istreambuf_iterator<char>(in)), {});
	ASSERT_TRUE(WIFEXITED(status)) << text;
	EXPECT_EQ(WEXITSTATUS(status), 0) << text;
	EXPECT_NE(text.find("shutdown requested"), std::string::npos) << text;
	EXPECT_NE(text.find("on SIGTERM"), std::string::npos) << text;
	EXPECT_TRUE(fs::exists(d / "sigterm.jsonl")); // finished: renamed into place
}

struct Rgb {
	int width = 0, height = 0;
	std::vector<uint8_t> pixels;
	int count(uint8_t r, uint8_t g, uint8_t b) const
	{
		int n = 0;
		for (size_t i = 0; i + 2 < pixels.size(); i += 3)
			n += pixels[i] == r && pixels[i + 1] == g && pixels[i + 2] == b;
		return n;
	}
};

Rgb readRgb(const fs::path &file)
{
	Rgb out;
	png_image img{};
	img.version = PNG_IMAGE_VERSION;
	if (!png_image_begin_read_from_file(&img, file.c_str()))
		return out;
	img.format = PNG_FORMAT_RGB;
	out.pixels.resize(PNG_IMAGE_SIZE(img));
	if (png_image_finish_read(&img, nullptr, out.pixels.data(), 0, nullptr)) {
		out.width = static_cast<int>(img.width);
		out.height = static_cast<int>(img.height);
	}
	return out;
}

TEST_F(RunReplay, VisDrawsTheHypothesisOfEachIterationOverTheCrop)
{
	const fs::path &d = *dir_;
	const fs::path vis = freshTempDir("run_vis");
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --frames 1 --vis " + q(vis) +
				 " --out file:" + q(vis / "poses.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const RunOutput got = readRunOutput(vis / "poses.jsonl");
	ASSERT_EQ(got.poses.size(), 1u);
	const json &pose = got.poses.begin()->second;
	const int iterations = pose["iterations"].get<int>();
	ASSERT_GT(iterations, 0);

	// The crop: frame 0's box (as pixels) with a margin of w/8 + 4, clipped to 640 x 480.
	std::ifstream in(d / "boxes.jsonl");
	std::string line;
	std::getline(in, line);
	const json box = json::parse(line)["boxes"][0]["bbox"];
	const int bx = static_cast<int>(std::floor(box[0].get<double>()));
	const int by = static_cast<int>(std::floor(box[1].get<double>()));
	const int bw = static_cast<int>(std::ceil(box[2].get<double>()));
	const int bh = static_cast<int>(std::ceil(box[3].get<double>()));
	const int x0 = std::max(0, bx - (bw / 8 + 4)), x1 = std::min(640, bx + bw + bw / 8 + 4);
	const int y0 = std::max(0, by - (bh / 8 + 4)), y1 = std::min(480, by + bh + bh / 8 + 4);

	for (int k = 0; k <= iterations; ++k) {
		const fs::path file = vis / ("f000000_o20_it" + std::to_string(k) + ".png");
		ASSERT_TRUE(fs::exists(file)) << file << "\n" << r.output;
		const Rgb img = readRgb(file);
		EXPECT_EQ(img.width, x1 - x0) << file;
		EXPECT_EQ(img.height, y1 - y0) << file;
		EXPECT_GT(img.count(230, 40, 40), 20) << "no hypothesis outline in " << file;
	}
	EXPECT_FALSE(fs::exists(vis / ("f000000_o20_it" + std::to_string(iterations + 1) + ".png")));
	const Rgb final = readRgb(vis / "f000000_o20_final.png");
	EXPECT_EQ(final.width, x1 - x0);
	EXPECT_GT(final.count(40, 220, 60), 20) << "no final outline";
	EXPECT_GT(final.count(230, 200, 0), 2 * (bw + bh) - 8) << "no box frame";
	EXPECT_NE(r.output.find("pictures in"), std::string::npos) << r.output;
}

TEST_F(RunReplay, RealTimeReplayDropsFramesOlderThanTheBudget)
{
	// 30 fps, a 1 ms budget: frame 0 is taken at once; estimating it takes far
	// longer than the 67 ms until frames 1 and 2 are due, so both are late.
	const fs::path &d = *dir_;
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --real-time --drop-frames-older-than-ms 1" +
				 " --out file:" + q(d / "late.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("end of stream; frames 3 processed 1 late 2"), std::string::npos) << r.output;
	const RunOutput got = readRunOutput(d / "late.jsonl");
	ASSERT_EQ(got.poses.size(), 1u);
	EXPECT_EQ(got.poses.begin()->first.frame, 0);
	expectSamePose(got.poses.begin()->second, estimateRows(d / "est.csv").begin()->second);
}

// --budget-ms sets the frame's estimation budget: with almost none, every
// box keeps its first slab's registration (no refinement, no ICP); 0 is
// unlimited, the poses of ihf estimate.
TEST_F(RunReplay, EstimationBudgetFromTheCommandLine)
{
	const fs::path &d = *dir_;
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --budget-ms 0.001 --out file:" +
				 q(d / "tight.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const RunOutput tight = readRunOutput(d / "tight.jsonl");
	ASSERT_FALSE(tight.poses.empty());
	std::set<int64_t> frames;
	for (const auto &[key, pose] : tight.poses) {
		EXPECT_EQ(pose["iterations"].get<int>(), 0) << pose.dump();
		EXPECT_FALSE(pose["icp"].get<bool>()) << pose.dump();
		frames.insert(key.frame);
	}
	// The stats line says what the budget cost: every frame and box overran,
	// already in the initial registration (never cut short), and every box's
	// refinement was cut.
	const std::string n = std::to_string(tight.poses.size());
	EXPECT_NE(r.output.find("budget 0.001 ms: overruns " + std::to_string(frames.size()) + " frames " + n +
				" boxes (" + n + " in the initial registration) cut-short " + n + " iterations 0 tight " + n),
		  std::string::npos)
		<< r.output;

	r = runIhf("run --config " + q(d / "device.toml") + " --budget-ms 0 --out file:" + q(d / "free.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto expected = estimateRows(d / "est.csv");
	EXPECT_EQ(r.output.find("budget "), std::string::npos) << r.output; // none to report
	const RunOutput free = readRunOutput(d / "free.jsonl");
	ASSERT_EQ(free.poses.size(), expected.size());
	for (const auto &[key, row] : expected) {
		auto it = free.poses.find(key);
		ASSERT_NE(it, free.poses.end());
		expectSamePose(it->second, row);
	}
	EXPECT_NE(runIhf("run --config " + q(d / "device.toml") + " --budget-ms -1").exitCode, 0);
}

TEST_F(RunReplay, BoxesInAndPosesOutOnAUnixSocket)
{
	const fs::path &d = *dir_;
	const fs::path sock = freshTempDir("run_socket") / "ihf.sock";
	std::vector<std::string> args = {ihfBinary().string(), "run", "--config", (d / "device.toml").string(),
					 "--boxes", "unix:" + sock.string(), "--out", "socket"};
	std::vector<char *> argv;
	for (auto &a : args)
		argv.push_back(a.data());
	argv.push_back(nullptr);
	const std::string err = (sock.parent_path() / "run.err").string();
	posix_spawn_file_actions_t fa;
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	pid_t pid = 0;
	ASSERT_EQ(posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ), 0);
	posix_spawn_file_actions_destroy(&fa);

	// The detector: connects once ihf listens, sends every box line, reads poses back.
	int s = -1;
	for (int i = 0; i < 100 && s < 0; ++i) {
		s = socket(AF_UNIX, SOCK_STREAM, 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		std::strncpy(a.sun_path, sock.c_str(), sizeof(a.sun_path) - 1);
		if (connect(s, reinterpret_cast<sockaddr *>(&a), sizeof(a)) != 0) {
			close(s);
			s = -1;
			std::this_thread::sleep_for(std::chrono::milliseconds(50));
		}
	}
	ASSERT_GE(s, 0) << "ihf run never listened on " << sock;
	std::ifstream boxes(d / "boxes_unknown.jsonl");
	const std::string lines((std::istreambuf_iterator<char>(boxes)), {});
	ASSERT_EQ(write(s, lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
	const auto expected = estimateRows(d / "est.csv");
	std::string received;
	char buf[4096];
	ssize_t n;
	size_t newlines = 0;
	while (newlines < expected.size() + 1 && (n = read(s, buf, sizeof(buf))) > 0) {
		received.append(buf, n);
		newlines = std::count(received.begin(), received.end(), '\n');
	}
	close(s);
	int status = 0;
	ASSERT_EQ(waitpid(pid, &status, 0), pid);
	std::ifstream errIn(err);
	const std::string text((std::istreambuf_iterator<char>(errIn)), {});
	ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;

	// Every pose of ihf estimate, and the unknown object's error line.
	std::istringstream in(received);
	std::string line;
	size_t poses = 0, errors = 0;
	while (std::getline(in, line)) {
		json j = json::parse(line);
		if (j.contains("error")) {
			EXPECT_EQ(j["obj_id"], 99);
			++errors;
			continue;
		}
		auto it = expected.find({j["frame"].get<int>(), j["obj_id"].get<int>()});
		ASSERT_NE(it, expected.end()) << line;
		expectSamePose(j, it->second);
		++poses;
	}
	EXPECT_EQ(poses, expected.size()) << received << text;
	EXPECT_EQ(errors, 1u);
}

TEST_F(RunReplay, UsageErrors)
{
	const fs::path &d = *dir_;
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --source bogus:x");
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("unknown scheme 'bogus'"), std::string::npos) << r.output;
	r = runIhf("run");
	EXPECT_EQ(r.exitCode, 2) << r.output;
	r = runIhf("run --help");
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("--vis"), std::string::npos);
}

#ifdef IHF_TEST_SYSTEMD
// As a systemd Type=notify service with a watchdog: READY=1 with the first
// loop iteration, WATCHDOG=1 on every other one, STOPPING=1 at the end, as
// datagrams to the socket NOTIFY_SOCKET names (bound here, as systemd would).
TEST_F(RunReplay, NotifiesSystemdReadyWatchdogAndStopping)
{
	const fs::path &d = *dir_;
	const fs::path sockPath = d / "notify.sock";
	::unlink(sockPath.c_str());
	const int s = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	ASSERT_GE(s, 0);
	sockaddr_un a{};
	a.sun_family = AF_UNIX;
	std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", sockPath.c_str());
	ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr *>(&a), sizeof(a)), 0) << std::strerror(errno);

	::setenv("NOTIFY_SOCKET", sockPath.c_str(), 1);
	CommandResult r = runIhf("run --config " + q(d / "device.toml") + " --out file:" + q(d / "notify.jsonl"));
	::unsetenv("NOTIFY_SOCKET");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("frames 3 processed 3"), std::string::npos) << r.output;

	std::vector<std::string> got;
	char buf[512];
	for (ssize_t n; (n = ::recv(s, buf, sizeof(buf), MSG_DONTWAIT)) >= 0;)
		got.emplace_back(buf, static_cast<size_t>(n));
	::close(s);
	::unlink(sockPath.c_str());
	// 3 frames and the end of the stream: 4 iterations.
	EXPECT_EQ(got, (std::vector<std::string>{"READY=1\nWATCHDOG=1", "WATCHDOG=1", "WATCHDOG=1",
						 "WATCHDOG=1", "STOPPING=1"}));
}
#endif

} // namespace
} // namespace ihf::test
