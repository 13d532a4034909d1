// SPDX-License-Identifier: MIT
#include "core/pose/median_select.h"

#include <algorithm>
#include <array>

namespace ihf {

namespace {

// Below this many values the ranks are counted.
constexpr int kRankedValues = 24;

// The k-th smallest of v[0, n) by counting each value's rank: no branch
// but the last, so it runs on vector lanes.
float rankSelect(const float *v, int n, int k)
{
	for (int i = 0; i < n; ++i) {
		const float x = v[i];
		int below = 0, atMost = 0;
		for (int j = 0; j < n; ++j) {
			below += v[j] < x;
			atMost += v[j] <= x;
		}
		if (below <= k && k < atMost)
			return x;
	}
	return v[k]; // not reached for finite values
}

} // namespace

// Each round splits the values around a median-of-three pivot into the
// other buffer without a branch per value, and goes on with the side
// holding the k-th; the pivot's equals end it. A few values are ranked.
float medianSelect(std::span<float> values)
{
	int n = static_cast<int>(values.size());
	int k = n / 2;
	if (n == 0)
		return 0.0f;
	if (values.size() > kMaxMedianValues) {
		std::nth_element(values.begin(), values.begin() + k, values.end());
		return values[static_cast<size_t>(k)];
	}
	std::array<float, kMaxMedianValues> other;
	float *const buffers[2] = {values.data(), other.data()};
	int in = 0; // the buffer src lies in
	const float *src = values.data();
	while (n > kRankedValues) {
		float *const dst = buffers[1 - in];
		const float a = src[0], b = src[n / 2], c = src[n - 1];
		const float pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
		// Smaller values fill dst from the front, larger from the back;
		// each is written at both free ends and kept by the one it counts for.
		int below = 0, above = 0;
		for (int j = 0; j < n; ++j) {
			const float x = src[j];
			dst[below] = x;
			dst[n - 1 - above] = x;
			below += x < pivot;
			above += x > pivot;
		}
		if (k < below) {
			src = dst;
			n = below;
		} else if (k >= n - above) {
			k -= n - above;
			src = dst + (n - above);
			n = above;
		} else {
			return pivot;
		}
		in = 1 - in;
	}
	return rankSelect(src, n, k);
}

} // namespace ihf
