// SPDX-License-Identifier: MIT
#pragma once

// Atomic file replacement: the content goes to "<file>.tmp-<pid>-<n>" in the
// same folder and is renamed over <file> only when fully written, so readers
// see either the old file or the new one, never a half file. Parent folders
// are created as needed; on any failure the temporary file is removed. An
// existing device or FIFO (/dev/null) is written in place (special_file.h).

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string_view>

#include "core/common/expected.h"

namespace ihf {

Status writeFileAtomic(const std::filesystem::path &file, std::string_view contents);

// fill writes the content into the open temporary stream; an error it returns
// (its message should name file) aborts the write and is passed on.
Status writeFileAtomic(const std::filesystem::path &file,
		       const std::function<Status(std::FILE *stream)> &fill);

} // namespace ihf
