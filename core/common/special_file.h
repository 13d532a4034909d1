// SPDX-License-Identifier: MIT
#pragma once

// Outputs that exist and are neither regular files nor folders (/dev/null,
// /dev/stdout, a FIFO, a socket) are written in place: replacing them by a
// rename, as the atomic writers do with files, would turn /dev/null into a
// regular file when run as root (seen with `ihf estimate --out /dev/null`).

#include <filesystem>
#include <system_error>

namespace ihf {

inline bool isSpecialFile(const std::filesystem::path &file)
{
	std::error_code ec;
	const std::filesystem::file_status s = std::filesystem::status(file, ec);
	return !ec && std::filesystem::exists(s) && !std::filesystem::is_regular_file(s) &&
	       !std::filesystem::is_directory(s);
}

} // namespace ihf
