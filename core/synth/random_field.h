// SPDX-License-Identifier: MIT
#pragma once

// Spatially correlated random fields over an image grid. Real sensor errors
// are not independent per pixel: the Kinect matches 9x9-ish blocks of the
// speckle pattern, so its noise, edge raggedness and dropouts come in small
// blobs. A box-blurred white-noise field renormalised to unit variance gives
// that correlation with a known per-pixel distribution.

#include <vector>

#include "core/synth/synth_random.h"

namespace ihf {

struct RandomField {
	int width = 0;
	int height = 0;
	std::vector<float> values; // row-major

	float at(int x, int y) const { return values[static_cast<size_t>(y) * width + x]; }
};

// Independent standard normal per pixel.
RandomField whiteNoiseField(int width, int height, SynthRandom &rng);

// Standard normal per pixel, correlated over a (2 radius + 1)^2 window.
RandomField correlatedNormalField(int width, int height, int radius, SynthRandom &rng);

// Uniform in [0, 1) per pixel with the correlation of correlatedNormalField:
// thresholding it at p marks a fraction p of the pixels, in blobs.
RandomField correlatedUniformField(int width, int height, int radius, SynthRandom &rng);

// Standard normal cumulative distribution.
double normalCdf(double x);

} // namespace ihf
