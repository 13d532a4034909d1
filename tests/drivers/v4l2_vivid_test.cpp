// SPDX-License-Identifier: MIT
// ihf's V4L2 source against the real kernel: Debian's kernel with the vivid
// test driver, booted under QEMU (TCG) by vivid/run-vivid.sh (the ctest
// fixture v4l2_vivid_vm, run once before these tests), runs the capture
// checks of vivid/capture_main.cpp; each check's line from the VM console is
// one test here. Skipped only when qemu-system-x86_64 is missing.

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

namespace {

struct VmRun {
	bool qemu = false;
	std::string console;
	std::map<std::string, std::pair<bool, std::string>> checks; // name -> pass, detail
	bool finished = false;
	bool passed = false;
};

std::string readFile(const std::string &path)
{
	std::ifstream in(path, std::ios::binary);
	return {std::istreambuf_iterator<char>(in), {}};
}

const VmRun &vm()
{
	static VmRun run = [] {
		VmRun r;
		const std::string work = IHF_VIVID_WORK;
		r.qemu = !std::ifstream(work + "/qemu-missing").good();
		if (!r.qemu)
			return r;
		r.console = readFile(work + "/console.log");
		std::istringstream lines(r.console);
		std::string line;
		while (std::getline(lines, line)) {
			if (!line.empty() && line.back() == '\r')
				line.pop_back();
			const size_t at = line.find("IHF-V4L2 CHECK ");
			if (at != std::string::npos) {
				std::istringstream f(line.substr(at + 15));
				std::string name, verdict, detail;
				f >> name >> verdict;
				std::getline(f, detail);
				r.checks[name] = {verdict == "PASS", detail};
			}
			if (line.find("IHF-V4L2-RESULT") != std::string::npos) {
				r.finished = true;
				r.passed = line.find("IHF-V4L2-RESULT PASS") != std::string::npos;
			}
		}
		return r;
	}();
	return run;
}

void expectCheck(const char *name)
{
	const VmRun &r = vm();
	if (!r.qemu)
		GTEST_SKIP() << "qemu-system-x86_64 is not installed (toolchain/debian12-packages.txt has it)";
	ASSERT_FALSE(r.console.empty()) << "no console log in " IHF_VIVID_WORK " (did the fixture test v4l2_vivid_vm run?)";
	auto it = r.checks.find(name);
	ASSERT_NE(it, r.checks.end()) << "no result for check " << name << "\n--- console ---\n" << r.console;
	EXPECT_TRUE(it->second.first) << name << ":" << it->second.second;
	std::printf("%s:%s\n", name, it->second.second.c_str());
}

TEST(V4l2Vivid, FindsTheVividCaptureNode) { expectCheck("node"); }
TEST(V4l2Vivid, Captures30Y16FramesWithEintrRetried) { expectCheck("capture"); }
TEST(V4l2Vivid, PollTimeoutGivesKTimeout) { expectCheck("timeout"); }
TEST(V4l2Vivid, BufFlagErrorIsSkippedAndCounted) { expectCheck("bufError"); }
TEST(V4l2Vivid, DeviceRemovalIsAnErrorAndReopenWorksWhenItReturns) { expectCheck("removal"); }

TEST(V4l2Vivid, RunLoopReportsTheRemovalAndReopens) { expectCheck("runLoop"); }

TEST(V4l2Vivid, TheVmRanToTheEnd)
{
	const VmRun &r = vm();
	if (!r.qemu)
		GTEST_SKIP() << "qemu-system-x86_64 is not installed";
	EXPECT_TRUE(r.finished) << r.console;
	EXPECT_EQ(r.console.find("INSMOD-FAILED"), std::string::npos) << r.console;
	EXPECT_EQ(r.console.find("Oops"), std::string::npos) << r.console;
	EXPECT_EQ(r.console.find("BUG:"), std::string::npos) << r.console;
}

} // namespace
