// SPDX-License-Identifier: MIT
// Guest instructions executed by a program under qemu-user, from qemu's own
// log (Debian 12's qemu-user-static has no TCG plugins). Run the program with
//   qemu-aarch64-static -d in_asm,exec,nochain -D LOG ...
// and feed LOG (a FIFO: the log is gigabytes) to this program on stdin:
//   "IN: sym" blocks list each translation block's guest instructions once,
//   at translation ("0x...:  insn" lines); every execution of a block logs
//   "Trace N: host [cs_base/pc/flags/cflags] sym" (nochain: every execution
//   goes through the main loop, so none is missed). Instructions = sum over
//   executions of the executed block's instruction count.
// Prints executed instructions, block executions and translations.
// Build: g++ -O2 -std=c++20 -o qemu-insn-count toolchain/qemu-insn-count.cpp

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

int main()
{
	std::unordered_map<uint64_t, uint32_t> blockSize; // guest pc -> instructions
	uint64_t executed = 0, executions = 0, translations = 0, unknown = 0;
	uint64_t inBlock = 0, blockPc = 0;
	bool inAsm = false;
	char line[4096];
	auto closeBlock = [&] {
		if (inAsm && inBlock)
			blockSize[blockPc] = static_cast<uint32_t>(inBlock);
		inAsm = false;
		inBlock = 0;
	};
	while (std::fgets(line, sizeof(line), stdin)) {
		if (std::strncmp(line, "Trace ", 6) == 0) {
			closeBlock();
			// "Trace 0: 0x7f.. [0000000000000000/0000005500001234/...]"
			const char *b = std::strchr(line, '[');
			const char *s = b ? std::strchr(b, '/') : nullptr;
			if (!s)
				continue;
			const uint64_t pc = std::strtoull(s + 1, nullptr, 16);
			++executions;
			auto it = blockSize.find(pc);
			if (it == blockSize.end())
				++unknown;
			else
				executed += it->second;
		} else if (std::strncmp(line, "IN:", 3) == 0) {
			closeBlock();
			inAsm = true;
			++translations;
		} else if (inAsm && std::strncmp(line, "0x", 2) == 0) {
			// "0x0000005500001234:  d503201f      nop"
			const uint64_t pc = std::strtoull(line, nullptr, 16);
			if (inBlock == 0)
				blockPc = pc;
			++inBlock;
		} else if (inAsm && line[0] == '\n') {
			closeBlock();
		}
	}
	closeBlock();
	std::printf("instructions %llu\nblock_executions %llu\ntranslations %llu\n"
		    "executions_of_unlisted_blocks %llu\n",
		    static_cast<unsigned long long>(executed),
		    static_cast<unsigned long long>(executions),
		    static_cast<unsigned long long>(translations),
		    static_cast<unsigned long long>(unknown));
	return unknown ? 1 : 0;
}
