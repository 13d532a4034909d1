// SPDX-License-Identifier: MIT
#include "tests/common/test_paths.h"

#include <array>
#include <cstdio>
#include <sys/wait.h>

namespace ihf::test {

CommandResult runIhf(const std::string &args)
{
	CommandResult result;
	std::string cmd = "'"; // appended: GCC 12 warns falsely on "literal" + string at -O3
	cmd.append(ihfBinary().string()).append("' ").append(args).append(" 2>&1");
#ifdef IHF_TEST_EMULATOR
	cmd = std::string(IHF_TEST_EMULATOR) + " " + cmd;
#endif
	FILE *pipe = popen(cmd.c_str(), "r");
	if (!pipe)
		return result;
	std::array<char, 4096> buf;
	size_t n;
	while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
		result.output.append(buf.data(), n);
	int status = pclose(pipe);
	result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
	return result;
}

} // namespace ihf::test
