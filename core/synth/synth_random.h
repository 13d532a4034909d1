// SPDX-License-Identifier: MIT
#pragma once

// Deterministic random numbers for the scene synthesizer. The engine is
// std::mt19937_64, whose output sequence the standard fixes; the
// distributions are our own (std::*_distribution output is
// implementation-defined), so one seed gives the same scenes on every
// standard library.

#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Core>

namespace ihf {

// splitmix64 finaliser: spreads a structured key (seed, object, image) over
// 64 bits so that neighbouring keys give unrelated streams.
uint64_t mixSeed(uint64_t a, uint64_t b);

class SynthRandom
{
public:
	explicit SynthRandom(uint64_t seed) : engine_(seed) {}

	uint64_t next() { return engine_(); }

	// Uniform in [0, 1) with 53 random bits.
	double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
	double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }
	// Uniform integer in [0, n), unbiased (rejection of the short last bucket).
	uint64_t below(uint64_t n);
	int uniformInt(int lo, int hi) { return lo + static_cast<int>(below(static_cast<uint64_t>(hi - lo) + 1)); }
	bool chance(double p) { return uniform01() < p; }
	// exp of a uniform draw in [log lo, log hi): as likely in every octave.
	double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
	// Standard normal by Box-Muller (both values of a pair are used).
	double normal();
	double normal(double mean, double sigma) { return mean + sigma * normal(); }
	// Uniformly distributed direction on the unit sphere.
	Eigen::Vector3d unitVector();

private:
	std::mt19937_64 engine_;
	double spare_ = 0;
	bool hasSpare_ = false;
};

} // namespace ihf
