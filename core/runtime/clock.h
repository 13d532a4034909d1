// SPDX-License-Identifier: MIT
#pragma once

// The time source of budgets and stage counters, injected so that tests can
// drive time themselves (never the wall clock in a test).

#include <chrono>
#include <cstdint>

namespace ihf {

class Clock
{
public:
	virtual ~Clock() = default;
	// Monotonic nanoseconds; only differences mean anything.
	virtual int64_t nowNs() const = 0;
};

class SteadyClock final : public Clock
{
public:
	int64_t nowNs() const override
	{
		return std::chrono::duration_cast<std::chrono::nanoseconds>(
			       std::chrono::steady_clock::now().time_since_epoch())
			.count();
	}
};

} // namespace ihf
