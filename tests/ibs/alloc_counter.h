// SPDX-License-Identifier: MIT
#pragma once

// Counts calls of the global operator new in the test executable that links
// alloc_counter.cpp, so tests can check that per-frame calls allocate nothing.

#include <cstddef>

namespace ihf::test {

size_t allocationCount();

} // namespace ihf::test
