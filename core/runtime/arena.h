// SPDX-License-Identifier: MIT
#pragma once

// A bump allocator over one block allocated at start-up (the frame path's
// only memory). allocate<T>(n) hands out 64-byte aligned spans from the
// block; nothing is ever freed one by one. mark()/rewind() give scratch
// memory for one call (ArenaScope does it for a scope), so persistent
// buffers sit at the bottom and per-call scratch above them, and the
// high-water mark tells what the largest call really needed: the arena can
// be sized from measurement.
//
// Failure is a value: create() and allocate() return Errc::kCapacity (the
// message is short enough for std::string's in-place buffer, so even a
// failing allocate() does not touch the heap). Only trivially destructible
// types may live in the arena, since it runs no destructors.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>

#include "core/common/expected.h"

namespace ihf {

class Arena
{
public:
	static constexpr size_t kAlignment = 64;

	// Bytes an allocation of n objects of T takes in the arena.
	template<typename T>
	static constexpr size_t footprint(size_t n)
	{
		return roundUp(n * sizeof(T));
	}

	static constexpr size_t roundUp(size_t bytes)
	{
		return (bytes + kAlignment - 1) & ~(kAlignment - 1);
	}

	Arena() = default; // empty: every allocation of n > 0 fails
	~Arena();
	Arena(Arena &&other) noexcept;
	Arena &operator=(Arena &&other) noexcept;
	Arena(const Arena &) = delete;
	Arena &operator=(const Arena &) = delete;

	// The one heap allocation (capacity rounded up to kAlignment).
	static Expected<Arena> create(size_t capacity);

	// n default-initialised objects (indeterminate values for trivial types).
	template<typename T>
	Expected<std::span<T>> allocate(size_t n)
	{
		static_assert(std::is_trivially_destructible_v<T>, "the arena runs no destructors");
		static_assert(alignof(T) <= kAlignment);
		if (n > (SIZE_MAX - kAlignment) / sizeof(T) || footprint<T>(n) > capacity_ - used_)
			return Error{Errc::kCapacity, "arena full"};
		T *p = reinterpret_cast<T *>(base_ + used_);
		used_ += footprint<T>(n);
		if (used_ > highWater_)
			highWater_ = used_;
		std::uninitialized_default_construct_n(p, n);
		return std::span<T>(p, n);
	}

	size_t capacity() const { return capacity_; }
	size_t used() const { return used_; }
	size_t remaining() const { return capacity_ - used_; }
	size_t highWater() const { return highWater_; }

	// Scratch: everything allocated after mark() is released by rewind().
	size_t mark() const { return used_; }
	void rewind(size_t mark)
	{
		if (mark < used_)
			used_ = mark;
	}

private:
	std::byte *base_ = nullptr;
	size_t capacity_ = 0;
	size_t used_ = 0;
	size_t highWater_ = 0;
};

// Releases the scratch allocated during its lifetime.
class ArenaScope
{
public:
	explicit ArenaScope(Arena &arena) : arena_(arena), mark_(arena.mark()) {}
	~ArenaScope() { arena_.rewind(mark_); }
	ArenaScope(const ArenaScope &) = delete;
	ArenaScope &operator=(const ArenaScope &) = delete;

private:
	Arena &arena_;
	size_t mark_;
};

// Adds up footprints to size an arena before creating it. Its allocate()
// mirrors Arena's but hands out empty spans, so one layout function written
// against either type both sizes and carves (see arenaTake()).
struct ArenaSizer {
	size_t bytes = 0;

	// Saturates at SIZE_MAX, which no arena can be created with.
	template<typename T>
	ArenaSizer &add(size_t n)
	{
		const size_t limit = SIZE_MAX - Arena::kAlignment;
		if (n > limit / sizeof(T) || Arena::footprint<T>(n) > limit - bytes)
			bytes = SIZE_MAX;
		else
			bytes += Arena::footprint<T>(n);
		return *this;
	}

	template<typename T>
	Expected<std::span<T>> allocate(size_t n)
	{
		add<T>(n);
		return std::span<T>();
	}
};

// out = n objects from an Arena or ArenaSizer; false when the arena is full.
template<typename A, typename T>
bool arenaTake(A &arena, std::span<T> &out, size_t n)
{
	auto r = arena.template allocate<T>(n);
	if (!r)
		return false;
	out = *r;
	return true;
}

} // namespace ihf
