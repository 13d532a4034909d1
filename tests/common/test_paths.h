// SPDX-License-Identifier: MIT
#pragma once

// Paths the build hands to every test: shared data, sources, the CLI.

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace ihf::test {

inline std::filesystem::path sharedDir() { return IHF_SHARED_DIR; }
inline std::filesystem::path lmoDir() { return sharedDir() / "data" / "lmo"; }
inline std::filesystem::path sourceDir() { return IHF_SOURCE_DIR; }
inline std::filesystem::path ihfBinary() { return IHF_BINARY; }
// The runtime tests' forest, written on amd64 (tests/data).
inline std::filesystem::path goldenForest() { return sourceDir() / "tests" / "data" / "golden_forest_amd64.ihf"; }

// A fresh, empty folder under the system temp dir for one test. The
// process id keeps parallel processes apart (ctest -j runs the cases of one
// suite as separate processes, and other checkouts on the machine use the
// same names); without it one process's SetUp deletes another's files.
inline std::filesystem::path freshTempDir(const std::string &name)
{
	auto dir = std::filesystem::temp_directory_path() /
		   ("ihf_test_" + name + "_" + std::to_string(::getpid()));
	std::filesystem::remove_all(dir);
	std::filesystem::create_directories(dir);
	return dir;
}

// The path in single quotes, for a shell command line. Built by appending:
// "'" + string trips a GCC 12 -Wstringop-overflow false positive.
inline std::string quoted(const std::filesystem::path &p)
{
	return std::string(1, '\'').append(p.string()).append(1, '\'');
}

struct CommandResult {
	int exitCode = -1;
	std::string output; // stdout and stderr together
};

// Runs `ihf ARGS` through the shell, capturing stdout+stderr.
CommandResult runIhf(const std::string &args);

} // namespace ihf::test
