// SPDX-License-Identifier: MIT
#include "core/runtime/arena.h"

#include <cstdlib>
#include <utility>

namespace ihf {

Arena::~Arena()
{
	std::free(base_);
}

Arena::Arena(Arena &&other) noexcept
	: base_(std::exchange(other.base_, nullptr)), capacity_(std::exchange(other.capacity_, 0)),
	  used_(std::exchange(other.used_, 0)), highWater_(std::exchange(other.highWater_, 0))
{
}

Arena &Arena::operator=(Arena &&other) noexcept
{
	if (this != &other) {
		std::free(base_);
		base_ = std::exchange(other.base_, nullptr);
		capacity_ = std::exchange(other.capacity_, 0);
		used_ = std::exchange(other.used_, 0);
		highWater_ = std::exchange(other.highWater_, 0);
	}
	return *this;
}

Expected<Arena> Arena::create(size_t capacity)
{
	Arena arena;
	if (capacity == 0)
		return arena;
	if (capacity > SIZE_MAX - kAlignment)
		return makeError(Errc::kCapacity, "Arena: requested capacity overflows");
	const size_t bytes = roundUp(capacity);
	arena.base_ = static_cast<std::byte *>(std::aligned_alloc(kAlignment, bytes));
	if (!arena.base_)
		return makeError(Errc::kCapacity, "Arena: cannot allocate " + std::to_string(bytes) + " bytes");
	arena.capacity_ = bytes;
	return arena;
}

} // namespace ihf
