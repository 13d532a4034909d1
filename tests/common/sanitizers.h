// SPDX-License-Identifier: MIT
#pragma once

// IHF_TEST_ASAN: defined when the tests are built with AddressSanitizer
// (GCC's __SANITIZE_ADDRESS__, clang's __has_feature). It owns malloc and
// free (allocation counters hook into its allocator), holds freed memory in
// quarantine (the resident set grows on purpose) and checks every access,
// so loops that only repeat what one pass checks are run shorter.

#if defined(__SANITIZE_ADDRESS__)
#define IHF_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define IHF_TEST_ASAN 1
#endif
#endif
