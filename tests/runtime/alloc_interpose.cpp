// SPDX-License-Identifier: MIT
#include "tests/runtime/alloc_interpose.h"

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <new>

#include "tests/common/sanitizers.h"

#ifndef IHF_TEST_ASAN
extern "C" {
void *__libc_malloc(size_t size);
void *__libc_calloc(size_t count, size_t size);
void *__libc_realloc(void *p, size_t size);
void __libc_free(void *p);
void *__libc_memalign(size_t alignment, size_t size);
}
#endif

namespace {
std::atomic<uint64_t> gAllocations{0};

void count()
{
	gAllocations.fetch_add(1, std::memory_order_relaxed);
}
} // namespace

#ifdef IHF_TEST_ASAN
// AddressSanitizer owns malloc & co. (its own allocator, red zones): a
// definition here would hand it glibc's blocks. Its allocator calls these
// hooks on every allocation and free instead, operator new included.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*mallocHook)(const volatile void *, size_t),
							   void (*freeHook)(const volatile void *));
namespace {
void onAllocation(const volatile void *, size_t) { count(); }
void onFree(const volatile void *) {}
// Before main, as the replacements below are in force from the start.
[[maybe_unused]] const int gHooksInstalled = __sanitizer_install_malloc_and_free_hooks(onAllocation, onFree);
} // namespace
#endif

namespace ihf::test {

uint64_t heapAllocations()
{
	return gAllocations.load(std::memory_order_relaxed);
}

} // namespace ihf::test

#ifndef IHF_TEST_ASAN
extern "C" {

void *malloc(size_t size)
{
	count();
	return __libc_malloc(size);
}

void *calloc(size_t n, size_t size)
{
	count();
	return __libc_calloc(n, size);
}

void *realloc(void *p, size_t size)
{
	count();
	return __libc_realloc(p, size);
}

void free(void *p)
{
	__libc_free(p);
}

void *memalign(size_t alignment, size_t size)
{
	count();
	return __libc_memalign(alignment, size);
}

void *aligned_alloc(size_t alignment, size_t size)
{
	count();
	return __libc_memalign(alignment, size);
}

int posix_memalign(void **out, size_t alignment, size_t size)
{
	count();
	if (alignment < sizeof(void *) || (alignment & (alignment - 1)) != 0)
		return EINVAL;
	void *p = __libc_memalign(alignment, size);
	if (!p)
		return ENOMEM;
	*out = p;
	return 0;
}

void *valloc(size_t size)
{
	count();
	return __libc_memalign(4096, size);
}

} // extern "C"

// Global operator new/delete, every variant: all go through the counted
// functions above.
namespace {

void *allocateOrThrow(size_t size)
{
	if (void *p = malloc(size ? size : 1))
		return p;
	throw std::bad_alloc();
}

void *allocateAlignedOrThrow(size_t size, std::align_val_t al)
{
	const size_t a = static_cast<size_t>(al) < sizeof(void *) ? sizeof(void *) : static_cast<size_t>(al);
	if (void *p = memalign(a, size ? size : 1))
		return p;
	throw std::bad_alloc();
}

} // namespace

void *operator new(size_t size) { return allocateOrThrow(size); }
void *operator new[](size_t size) { return allocateOrThrow(size); }
void *operator new(size_t size, const std::nothrow_t &) noexcept { return malloc(size ? size : 1); }
void *operator new[](size_t size, const std::nothrow_t &) noexcept { return malloc(size ? size : 1); }
void *operator new(size_t size, std::align_val_t al) { return allocateAlignedOrThrow(size, al); }
void *operator new[](size_t size, std::align_val_t al) { return allocateAlignedOrThrow(size, al); }
void *operator new(size_t size, std::align_val_t al, const std::nothrow_t &) noexcept
{
	return memalign(static_cast<size_t>(al) < sizeof(void *) ? sizeof(void *) : static_cast<size_t>(al),
			size ? size : 1);
}
void *operator new[](size_t size, std::align_val_t al, const std::nothrow_t &n) noexcept
{
	return operator new(size, al, n);
}

void operator delete(void *p) noexcept { free(p); }
void operator delete[](void *p) noexcept { free(p); }
void operator delete(void *p, size_t) noexcept { free(p); }
void operator delete[](void *p, size_t) noexcept { free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { free(p); }
void operator delete(void *p, std::align_val_t) noexcept { free(p); }
void operator delete[](void *p, std::align_val_t) noexcept { free(p); }
void operator delete(void *p, size_t, std::align_val_t) noexcept { free(p); }
void operator delete[](void *p, size_t, std::align_val_t) noexcept { free(p); }
void operator delete(void *p, std::align_val_t, const std::nothrow_t &) noexcept { free(p); }
void operator delete[](void *p, std::align_val_t, const std::nothrow_t &) noexcept { free(p); }
#endif // IHF_TEST_ASAN
