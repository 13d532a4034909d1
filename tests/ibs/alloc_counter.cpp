// SPDX-License-Identifier: MIT
// Replaces the global (non-aligned) operator new/delete with counting ones.

#include "tests/ibs/alloc_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<size_t> gAllocations{0};
}

namespace ihf::test {

size_t allocationCount()
{
	return gAllocations.load();
}

} // namespace ihf::test

void *operator new(std::size_t size)
{
	gAllocations.fetch_add(1);
	if (void *p = std::malloc(size ? size : 1))
		return p;
	throw std::bad_alloc();
}

void *operator new[](std::size_t size)
{
	return operator new(size);
}

void *operator new(std::size_t size, const std::nothrow_t &) noexcept
{
	gAllocations.fetch_add(1);
	return std::malloc(size ? size : 1);
}

void *operator new[](std::size_t size, const std::nothrow_t &) noexcept
{
	return operator new(size, std::nothrow);
}

void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
