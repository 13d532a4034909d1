// SPDX-License-Identifier: MIT
#include "core/synth/random_field.h"

#include <algorithm>
#include <cmath>

namespace ihf {

RandomField whiteNoiseField(int width, int height, SynthRandom &rng)
{
	RandomField f{width, height, std::vector<float>(static_cast<size_t>(width) * height)};
	for (float &v : f.values)
		v = static_cast<float>(rng.normal());
	return f;
}

namespace {

// Box blur of radius r along rows (step 1) or columns (step width), with
// clamped borders so every output averages exactly 2r + 1 samples.
void boxBlur1d(std::vector<float> &v, int width, int height, int r, bool alongRows)
{
	const int n = alongRows ? width : height;
	const int lines = alongRows ? height : width;
	std::vector<float> line(n), out(n);
	const float norm = 1.0f / static_cast<float>(2 * r + 1);
	for (int l = 0; l < lines; ++l) {
		for (int i = 0; i < n; ++i)
			line[i] = alongRows ? v[static_cast<size_t>(l) * width + i]
					    : v[static_cast<size_t>(i) * width + l];
		double sum = 0;
		for (int k = -r; k <= r; ++k)
			sum += line[std::clamp(k, 0, n - 1)];
		for (int i = 0; i < n; ++i) {
			out[i] = static_cast<float>(sum) * norm;
			sum += line[std::min(i + r + 1, n - 1)] - line[std::max(i - r, 0)];
		}
		for (int i = 0; i < n; ++i) {
			if (alongRows)
				v[static_cast<size_t>(l) * width + i] = out[i];
			else
				v[static_cast<size_t>(i) * width + l] = out[i];
		}
	}
}

} // namespace

RandomField correlatedNormalField(int width, int height, int radius, SynthRandom &rng)
{
	RandomField f = whiteNoiseField(width, height, rng);
	if (radius <= 0)
		return f;
	boxBlur1d(f.values, width, height, radius, true);
	boxBlur1d(f.values, width, height, radius, false);
	// Mean of (2r+1)^2 unit normals has variance 1/(2r+1)^2.
	const float gain = static_cast<float>(2 * radius + 1);
	for (float &v : f.values)
		v *= gain;
	return f;
}

double normalCdf(double x)
{
	return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

RandomField correlatedUniformField(int width, int height, int radius, SynthRandom &rng)
{
	RandomField f = correlatedNormalField(width, height, radius, rng);
	for (float &v : f.values)
		v = std::min(static_cast<float>(normalCdf(v)), 0.99999994f);
	return f;
}

} // namespace ihf
