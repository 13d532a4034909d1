// SPDX-License-Identifier: MIT
// A short soak of `ihf run`: a 30 Hz sequence of the bunny (ihf synth
// --sequence) played looped, tracked, with corrupt frames, truncated box
// lines and boxes of objects without a forest mixed in (soak_inputs.h).
// The run must count every bad frame, line and box, give exactly the poses
// of a run on the clean inputs (the bad ones left out), and keep its memory
// flat: the estimator's and the tracker's arena high-water marks the same
// after many passes as after two, and (outside AddressSanitizer, whose
// quarantine holds freed memory on purpose) the peak RSS within 1 MB.
// benchmarks/soak/run.sh is the long version (BENCHMARKS.md, Soak).

#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/app/soak_inputs.h"
#include "tests/common/sanitizers.h"
#include "tests/common/test_paths.h"

extern char **environ;

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The recording's passes. Under AddressSanitizer, which checks every access
// of every pass and runs the loop ~7x slower, four: still twice the two the
// memory comparison starts from.
#ifdef IHF_TEST_ASAN
constexpr int kPasses = 4;
#else
constexpr int kPasses = 10;
#endif

const auto q = test::quoted; // a path in single quotes, for the shell

struct Spawned {
	int exitCode = -1;
	std::string output; // stderr and stdout
	long maxRssKb = 0; // the process's peak resident set
};

// Runs ihf with these arguments and waits for it, with its resource use.
Spawned spawnIhf(std::vector<std::string> args, const fs::path &log)
{
	Spawned s;
	args.insert(args.begin(), ihfBinary().string());
	std::vector<char *> argv;
	for (auto &a : args)
		argv.push_back(a.data());
	argv.push_back(nullptr);
	posix_spawn_file_actions_t fa;
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	posix_spawn_file_actions_adddup2(&fa, 1, 2);
	pid_t pid = 0;
	const int spawned = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
	posix_spawn_file_actions_destroy(&fa);
	if (spawned != 0)
		return s;
	int status = 0;
	rusage use{};
	if (wait4(pid, &status, 0, &use) != pid)
		return s;
	s.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
	s.maxRssKb = use.ru_maxrss;
	std::ifstream in(log);
	s.output.assign(std::istreambuf_iterator<char>(in), {});
	return s;
}

// A number of the final stats line: the one after `key ` (e.g. "corrupt").
uint64_t statOf(const std::string &output, const std::string &key)
{
	const size_t end = output.rfind("ihf run: end of stream");
	const size_t max = output.rfind("ihf run: max frames reached");
	const size_t line = max != std::string::npos ? max : end;
	if (line == std::string::npos)
		return UINT64_MAX;
	std::smatch m;
	const std::string text = output.substr(line, output.find('\n', line) - line);
	if (!std::regex_search(text, m, std::regex("[ ;(]" + key + " ([0-9]+)")))
		return UINT64_MAX;
	return std::stoull(m[1].str());
}

// Each output line by (frame, object), without the timing fields; the
// lines of boxes of unknown objects and of malformed box lines apart.
struct RunLines {
	std::map<std::pair<int64_t, int>, json> byBox;
	uint64_t unknownObject = 0;
	uint64_t inputErrors = 0;
};

RunLines readLines(const fs::path &file)
{
	RunLines out;
	std::ifstream in(file);
	for (std::string line; std::getline(in, line);) {
		json j = json::parse(line);
		if (j.contains("error") && !j.contains("frame")) { // a malformed box line
			++out.inputErrors;
			continue;
		}
		if (j.contains("error") && j["error"].get<std::string>().rfind("no forest for object", 0) == 0) {
			++out.unknownObject;
			continue;
		}
		j.erase("latency_ms");
		j.erase("estimate_ms");
		const std::pair<int64_t, int> key{j["frame"].get<int64_t>(), j["obj_id"].get<int>()};
		EXPECT_EQ(out.byBox.count(key), 0u) << "two lines for frame " << key.first << ": " << line;
		out.byBox[key] = std::move(j);
	}
	return out;
}

TEST(RunSoak, LoopedRunCountsBadInputsKeepsThePosesAndItsMemoryFlat)
{
	const fs::path d = freshTempDir("run_soak");
	const fs::path models = sourceDir() / "config" / "models";
	// A slow camera, every box given, no object moved: the bad inputs are
	// the soak's only disturbance.
	CommandResult r = runIhf("synth --sequence --models " + q(models) +
				 " --objects 20 --sequences 1 --frames 12 --seed 3 --max-speed 0.1 --max-turn 20 "
				 "--miss 0 --change 0 --quiet --out " + q(d / "seq"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	std::ofstream(d / "train.toml") << "[views]\nviewpoints = 20\ninplane_steps = 2\n"
					   "[scales]\nfactors = [1.0]\nparts_per_image = 8\noccluded_views = 0.0\n"
					   "[parts]\nkind = \"variable\"\nmax_control_points = 256\n";
	r = runIhf("train --model " + q(models / "obj_000020.ply") + " --config " + q(d / "train.toml") + " --out " +
		   q(d / "bunny.ihf"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// A lean detector, unbudgeted so that poses do not depend on the machine.
	std::ofstream(d / "estimate.toml") << "[refinement]\niterations = 0\ndepth_windows = 1\ntarget_parts = 100\n"
					      "[icp]\ncandidates = 2\nforest_bests = false\n"
					      "registration_candidates = false\n"
					      "[view_search]\ninplane = 8\nrefine_top = 8\nviewpoints = 60\n"
					      "depth_centres = 1\n[half_turns]\ncandidates = 0\n";
	std::ofstream(d / "device.toml") << "[source]\nuri = \"recording:faulty.rec?loop=1\"\n"
					 << "[boxes]\ninput = \"file:faulty.boxes.jsonl\"\n"
					 << "[output]\nposes = \"file:faulty.jsonl\"\n"
					 << "[objects]\n20 = \"bunny.ihf\"\n"
					 << "[estimate]\nconfig = \"estimate.toml\"\n"
					 << "[tracking]\nenabled = true\n"
					 << "[run]\nstats_interval_s = 0\n";

	SoakFaults faults;
	faults.passes = kPasses;
	faults.corruptEvery = 5;
	faults.truncateEvery = 7;
	faults.unknownEvery = 3;
	auto made = makeSoakInputs(d / "seq" / "recordings" / "000001.rec",
				   d / "seq" / "recordings" / "000001.boxes.jsonl", faults, d);
	ASSERT_TRUE(made.ok()) << made.error().message;
	const SoakInputs &in = *made;
	ASSERT_EQ(in.corruptPerPass, 2u); // frames 4 and 9 of 12
	ASSERT_GT(in.truncatedLines, 0u);
	ASSERT_GT(in.unknownBoxes, 0u);

	const std::string frames = std::to_string(in.goodFrames);
	const std::string config = (d / "device.toml").string();
	const Spawned faulty = spawnIhf({"run", "--config", config, "--frames", frames}, d / "faulty.log");
	ASSERT_EQ(faulty.exitCode, 0) << faulty.output;
	const Spawned clean = spawnIhf({"run", "--config", config, "--frames", frames, "--source",
					"recording:" + (d / "clean.rec").string() + "?loop=1", "--boxes",
					"file:" + (d / "clean.boxes.jsonl").string(), "--out",
					"file:" + (d / "clean.jsonl").string()},
				       d / "clean.log");
	ASSERT_EQ(clean.exitCode, 0) << clean.output;

	// Every bad frame, line and box counted.
	const std::string &out = faulty.output;
	EXPECT_NE(out.find("max frames reached; frames " + frames + " processed " + frames), std::string::npos) << out;
	EXPECT_EQ(statOf(out, "corrupt"), in.corruptFrames) << out;
	EXPECT_EQ(statOf(out, "gaps"), 0u) << out;
	EXPECT_EQ(statOf(out, "unknown-object"), in.unknownBoxes) << out;
	EXPECT_EQ(statOf(out, "input-errors"), in.truncatedLines) << out;
	EXPECT_EQ(statOf(out, "malformed"), in.truncatedLines) << out;
	EXPECT_EQ(statOf(out, "box lines"), in.lines) << out;
	// Both of the tracker's paths ran: boxes tracked, and detected (each
	// track's start, and where the loop's jump or a gap loses it).
	EXPECT_GT(statOf(out, "tracked"), 0u) << out;
	EXPECT_GT(statOf(out, "detected"), 0u) << out;

	// The poses of the clean run, bit for bit, and no other lines.
	const RunLines got = readLines(d / "faulty.jsonl");
	const RunLines want = readLines(d / "clean.jsonl");
	EXPECT_EQ(got.unknownObject, in.unknownBoxes);
	EXPECT_EQ(got.inputErrors, in.truncatedLines);
	EXPECT_EQ(want.unknownObject + want.inputErrors, 0u);
	ASSERT_GT(want.byBox.size(), in.goodFrames / 2); // a pose for most frames
	EXPECT_EQ(got.byBox.size(), want.byBox.size());
	for (const auto &[key, line] : want.byBox) {
		auto it = got.byBox.find(key);
		ASSERT_NE(it, got.byBox.end()) << "no line for frame " << key.first;
		EXPECT_EQ(it->second, line) << "frame " << key.first;
	}
	EXPECT_GT(got.byBox.rbegin()->first.first, static_cast<int64_t>((faults.passes - 1) * in.indexSpan))
		<< "the last pass has poses";

	// Memory: the same arena high-water marks after two passes as after all,
	// and (without ASan) the same peak RSS within 1 MB.
	const std::string twoPasses = std::to_string(2 * (in.recordsPerPass - in.corruptPerPass));
	const Spawned early = spawnIhf({"run", "--config", config, "--frames", twoPasses, "--out",
					"file:" + (d / "early.jsonl").string()},
				       d / "early.log");
	ASSERT_EQ(early.exitCode, 0) << early.output;
	EXPECT_NE(statOf(early.output, "high-water"), UINT64_MAX) << early.output;
	EXPECT_EQ(statOf(early.output, "high-water"), statOf(out, "high-water")) << early.output << "\n" << out;
	EXPECT_NE(statOf(early.output, "tracker"), UINT64_MAX) << early.output;
	EXPECT_EQ(statOf(early.output, "tracker"), statOf(out, "tracker")) << early.output << "\n" << out;
#ifndef IHF_TEST_ASAN
	EXPECT_GT(early.maxRssKb, 0);
	EXPECT_LT(faulty.maxRssKb - early.maxRssKb, 1024)
		<< "peak RSS " << early.maxRssKb << " kB after two passes, " << faulty.maxRssKb << " kB after "
		<< faults.passes;
#endif
}

} // namespace
} // namespace ihf::test
