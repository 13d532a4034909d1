// SPDX-License-Identifier: MIT
#include "core/synth/synth_random.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace ihf {

uint64_t mixSeed(uint64_t a, uint64_t b)
{
	uint64_t z = a + 0x9e3779b97f4a7c15ull * (b + 1);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

uint64_t SynthRandom::below(uint64_t n)
{
	if (n <= 1)
		return 0;
	// Largest multiple of n representable; draws above it would bias the modulo.
	const uint64_t limit = std::numeric_limits<uint64_t>::max() -
			       std::numeric_limits<uint64_t>::max() % n;
	uint64_t r;
	do {
		r = next();
	} while (r >= limit);
	return r % n;
}

double SynthRandom::normal()
{
	if (hasSpare_) {
		hasSpare_ = false;
		return spare_;
	}
	// u1 in (0, 1] keeps the logarithm finite.
	const double u1 = 1.0 - uniform01();
	const double u2 = uniform01();
	const double r = std::sqrt(-2.0 * std::log(u1));
	const double a = 2.0 * std::numbers::pi * u2;
	spare_ = r * std::sin(a);
	hasSpare_ = true;
	return r * std::cos(a);
}

Eigen::Vector3d SynthRandom::unitVector()
{
	const double z = uniform(-1.0, 1.0);
	const double a = uniform(0.0, 2.0 * std::numbers::pi);
	const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
	return {s * std::cos(a), s * std::sin(a), z};
}

} // namespace ihf
