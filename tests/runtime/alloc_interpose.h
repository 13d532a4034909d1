// SPDX-License-Identifier: MIT
#pragma once

// Heap accounting for the zero-allocation test. The executable that links
// alloc_interpose.cpp defines malloc, calloc, realloc, free, the aligned
// variants and every global operator new/delete itself. With glibc a
// definition in the executable takes precedence over libc.so's for every
// caller (libstdc++'s operator new included, which would otherwise reach
// libc directly); the replacements forward to glibc's __libc_* entry points
// and count each allocating call. (__malloc_hook is gone since glibc 2.34,
// so interposition is the way.) Under AddressSanitizer, which brings its own
// allocator, the same calls are counted by the allocator's malloc hook
// (__sanitizer_install_malloc_and_free_hooks) instead.

#include <cstdint>

namespace ihf::test {

// Allocating calls (malloc, calloc, realloc, aligned allocations and
// operator new, which goes through malloc) since the program started.
uint64_t heapAllocations();

} // namespace ihf::test
