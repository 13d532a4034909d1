// SPDX-License-Identifier: MIT
// Do glibc's math functions give the same bits on this target as on amd64?
// Prints one hash per function over millions of random arguments; compare
// the output of a native and a cross build run under qemu (BENCHMARKS.md,
// Edge targets). Build with the project's flags that matter:
//   g++ -O2 -std=c++20 -ffp-contract=off toolchain/libm-agreement.cpp
//   aarch64-linux-gnu-g++ (same flags) ... ; qemu-aarch64-static -L /usr/aarch64-linux-gnu ./a.out
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>

template<class T>
static uint64_t bits(T v)
{
	uint64_t b = 0;
	std::memcpy(&b, &v, sizeof(T));
	return b;
}

// --expf-sweep: expf of every 7th float in [-8, 0) (the mean-shift kernel's
// range), one hash.
static int expfSweep()
{
	uint64_t h = 0, n = 0;
	const float lo = -8.0f;
	uint32_t last;
	std::memcpy(&last, &lo, 4);
	for (uint32_t b = 0x80000001u; b <= last; b += 7) {
		float x;
		std::memcpy(&x, &b, 4);
		h = h * 1000003ull ^ bits(std::exp(x));
		++n;
	}
	std::printf("expf sweep %llu values %016llx\n", static_cast<unsigned long long>(n),
		    static_cast<unsigned long long>(h));
	return 0;
}

int main(int argc, char **argv)
{
	if (argc > 1 && std::strcmp(argv[1], "--expf-sweep") == 0)
		return expfSweep();
	std::mt19937_64 rng(1);
	std::uniform_real_distribution<double> u(-4, 4), p(1e-6, 1000);
	const char *name[] = {"acos",          "acosf",           "atan2f",        "cosf",
			      "expf",          "logf",            "powf",          "sincos",
			      "sincosf",       "(float)atan2(d)", "(float)acos(d)", "atan2",
			      "acos(0.999x)"};
	constexpr int kN = sizeof(name) / sizeof(name[0]);
	uint64_t h[kN] = {};
	auto mix = [&](int k, uint64_t b) { h[k] = h[k] * 1000003ull ^ b; };
	for (int i = 0; i < 3000000; ++i) {
		const double x = u(rng), y = p(rng), z = u(rng);
		const float xf = static_cast<float>(x), yf = static_cast<float>(y), zf = static_cast<float>(z);
		mix(0, bits(std::acos(x / 4)));
		mix(1, bits(std::acos(xf / 4)));
		mix(2, bits(std::atan2(xf, zf)));
		mix(3, bits(std::cos(xf * 100)));
		mix(4, bits(std::exp(xf * 10)));
		mix(5, bits(std::log(yf)));
		mix(6, bits(std::pow(yf, xf)));
		double s, c;
		sincos(x * 100, &s, &c);
		mix(7, bits(s) ^ bits(c) * 3);
		float sf, cf;
		sincosf(xf * 100, &sf, &cf);
		mix(8, bits(sf) ^ bits(cf) * 3);
		mix(9, bits(static_cast<float>(std::atan2(double{xf}, double{zf}))));
		mix(10, bits(static_cast<float>(std::acos(double{xf} / 4))));
		mix(11, bits(std::atan2(x, z)));
		mix(12, bits(std::acos(x / 4 * 0.999)));
	}
	for (int k = 0; k < kN; ++k)
		std::printf("%-16s %016llx\n", name[k], static_cast<unsigned long long>(h[k]));
}
