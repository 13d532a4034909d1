// SPDX-License-Identifier: MIT
#pragma once

// The text of an errno value, for error messages that name the file and
// what failed on it.

#include <string>
#include <system_error>

namespace ihf {

inline std::string errnoText(int err)
{
	return std::error_code(err, std::generic_category()).message();
}

} // namespace ihf
