// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/pose/median_select.h"

namespace ihf {
namespace {

float nthElementMedian(std::vector<float> v)
{
	std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
	return v[v.size() / 2];
}

// Depth residuals as the view search sees them: a surface near zero, a
// wall behind, an occluder in front, and values repeated (pixels read
// twice) so that the pivot has equals.
std::vector<float> residuals(std::mt19937 &rng, size_t n)
{
	std::normal_distribution<float> surface(0.0f, 3.0f);
	std::uniform_real_distribution<float> far(-80.0f, 80.0f), pick(0.0f, 1.0f);
	std::vector<float> v(n);
	for (size_t i = 0; i < n; ++i) {
		const float p = pick(rng);
		v[i] = p < 0.5f ? surface(rng) : p < 0.8f ? far(rng) : p < 0.9f ? 55.0f : (i > 0 ? v[i - 1] : 1.0f);
	}
	return v;
}

TEST(MedianSelect, MatchesNthElementOnEverySize)
{
	std::mt19937 rng(7);
	for (size_t n = 1; n <= kMaxMedianValues + 40; ++n)
		for (int trial = 0; trial < 20; ++trial) {
			std::vector<float> v = residuals(rng, n);
			const float expected = nthElementMedian(v);
			ASSERT_EQ(medianSelect(v), expected) << "n " << n << " trial " << trial;
		}
}

TEST(MedianSelect, OrderedAndConstantInputs)
{
	for (size_t n : {1u, 2u, 23u, 24u, 25u, 64u, 128u, 255u, 256u}) {
		std::vector<float> up(n), down(n), same(n, -4.5f), two(n);
		for (size_t i = 0; i < n; ++i) {
			up[i] = static_cast<float>(i);
			down[i] = static_cast<float>(n - i);
			two[i] = i % 2 ? 1.0f : -1.0f;
		}
		EXPECT_EQ(medianSelect(up), static_cast<float>(n / 2)) << n;
		EXPECT_EQ(medianSelect(down), nthElementMedian(down)) << n;
		EXPECT_EQ(medianSelect(same), -4.5f) << n;
		EXPECT_EQ(medianSelect(two), nthElementMedian(two)) << n;
	}
	std::vector<float> none;
	EXPECT_EQ(medianSelect(none), 0.0f);
}

} // namespace
} // namespace ihf
