// SPDX-License-Identifier: MIT
#pragma once

// The readers under fuzzing take a path, as ihf gives them: each input is
// written to one file of this process (in /dev/shm when there is one, so
// that the write costs no disk), and the reader opens it.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace ihf::fuzz {

inline std::filesystem::path inputFile(const uint8_t *data, size_t size, const char *name)
{
	static const std::filesystem::path dir = [] {
		std::error_code ec;
		if (std::filesystem::is_directory("/dev/shm", ec))
			return std::filesystem::path("/dev/shm");
		return std::filesystem::temp_directory_path();
	}();
	const std::filesystem::path file = dir / ("ihf_fuzz_" + std::to_string(::getpid()) + "_" + name);
	std::FILE *f = std::fopen(file.c_str(), "wb");
	if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
		std::perror(file.c_str());
		std::abort();
	}
	return file;
}

} // namespace ihf::fuzz
