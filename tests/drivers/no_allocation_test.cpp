// SPDX-License-Identifier: MIT
// The frame path does not allocate: writing frames to a recording and
// playing them back (raw and zlib) while malloc, calloc and realloc are
// counted by test-only replacements.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

#include "drivers/recording_source.h"
#include "tests/common/sanitizers.h"
#include "tests/common/test_paths.h"
#include "tests/drivers/recording_test_util.h"

namespace {

std::atomic<bool> gCounting{false};
std::atomic<long> gAllocations{0};

void countAllocation()
{
	if (gCounting.load(std::memory_order_relaxed))
		gAllocations.fetch_add(1, std::memory_order_relaxed);
}

// Counts the allocations made while it is alive.
class AllocationCount
{
public:
	AllocationCount()
	{
		gAllocations = 0;
		gCounting = true;
	}
	~AllocationCount() { gCounting = false; }
	long count() const { return gAllocations.load(); }
};

} // namespace

#ifdef IHF_TEST_ASAN
// AddressSanitizer owns malloc & co.: its allocator calls these hooks on
// every allocation (operator new's and zlib's included) and free.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*mallocHook)(const volatile void *, size_t),
							   void (*freeHook)(const volatile void *));
namespace {
void onAllocation(const volatile void *, size_t) { countAllocation(); }
void onFree(const volatile void *) {}
[[maybe_unused]] const int gHooksInstalled = __sanitizer_install_malloc_and_free_hooks(onAllocation, onFree);
} // namespace
#else
// glibc's allocator under its internal names; the definitions below take
// the place of malloc & co. for the whole test executable (operator new and
// zlib allocate through them).
extern "C" {
void *__libc_malloc(size_t size);
void *__libc_calloc(size_t count, size_t size);
void *__libc_realloc(void *p, size_t size);
void __libc_free(void *p);

void *malloc(size_t size)
{
	countAllocation();
	return __libc_malloc(size);
}

void *calloc(size_t count, size_t size)
{
	countAllocation();
	return __libc_calloc(count, size);
}

void *realloc(void *p, size_t size)
{
	countAllocation();
	return __libc_realloc(p, size);
}

void free(void *p)
{
	__libc_free(p);
}
}
#endif

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class NoAllocation : public ::testing::TestWithParam<bool>
{
};

// The counting sees allocations at all (replaced malloc, or the
// sanitizer's hooks).
TEST(NoAllocationSelfCheck, AnAllocationIsCounted)
{
	AllocationCount allocs;
	auto *p = new std::vector<uint16_t>(1000);
	asm volatile("" : : "g"(p) : "memory");
	delete p;
	EXPECT_EQ(allocs.count(), 2); // the vector and its buffer
}

TEST_P(NoAllocation, WritingAndPlayingFrames)
{
	const bool compress = GetParam();
	const fs::path file = freshTempDir(compress ? "rec_noalloc_z" : "rec_noalloc_raw") / "s.rec";
	const TestStream s = testStream();

	RecordingWriterOptions o;
	o.compress = compress;
	o.reserveFrames = s.frames.size();
	auto writer = RecordingWriter::create(file, testHeader(), o);
	ASSERT_TRUE(writer.ok());
	{
		AllocationCount allocs;
		for (size_t i = 0; i < s.frames.size(); ++i)
			ASSERT_TRUE(writer->append({s.indices[i], s.deviceNs[i], s.hostNs[i]}, s.frames[i].view()).ok());
		EXPECT_EQ(allocs.count(), 0) << "RecordingWriter::append allocated";
	}
	ASSERT_TRUE(writer->finish().ok());

	for (Pacing pacing : {Pacing::kStep, Pacing::kRealTime}) {
		RecordingSourceOptions so;
		so.pacing = pacing;
		so.speed = 1e6; // real time, but without waiting long
		RecordingSource src(file, so);
		ASSERT_TRUE(src.open().ok());
		ASSERT_TRUE(src.start().ok());
		Frame f;
		size_t frames = 0;
		AllocationCount allocs;
		for (;;) {
			auto r = src.next(f, 1s);
			ASSERT_TRUE(r.ok());
			if (*r == FrameOutcome::kEndOfStream)
				break;
			frames += *r == FrameOutcome::kFrame;
		}
		EXPECT_EQ(frames, s.frames.size());
		EXPECT_EQ(allocs.count(), 0) << "RecordingSource::next allocated";
	}
}

INSTANTIATE_TEST_SUITE_P(RawAndZlib, NoAllocation, ::testing::Values(false, true));

} // namespace
} // namespace ihf::test
