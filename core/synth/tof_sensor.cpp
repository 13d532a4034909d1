// SPDX-License-Identifier: MIT
#include "core/synth/tof_sensor.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/synth/random_field.h"
#include "core/synth/sensor_output.h"
#include "core/synth/surface_incidence.h"

namespace ihf {

double tofAxialSigmaMm(const TofParams &p, double zMm, double theta)
{
	const double c = std::max(std::cos(std::clamp(theta, 0.0, std::numbers::pi / 2)), p.minCosine);
	return p.sigmaRefMm * (zMm / p.zRefMm) / std::sqrt(c);
}

double tofMixedDepth(double zOwn, double zOther, double coverage)
{
	// Both returns share the modulation phase in proportion to their
	// amplitudes; at the depth gaps of a tabletop the phases are close
	// enough that the phasor sum is the weighted mean of the depths.
	const double a = coverage / (zOwn * zOwn);
	const double b = (1.0 - coverage) / (zOther * zOther);
	return (a * zOwn + b * zOther) / (a + b);
}

DepthImage16 simulateTof(const SensorScene &scene, const CameraIntrinsics &K, const TofParams &p,
			 SynthRandom &rng, double depthScale)
{
	const int W = scene.depth.width, H = scene.depth.height;
	const size_t N = static_cast<size_t>(W) * H;
	auto idx = [W](int x, int y) { return static_cast<size_t>(y) * W + x; };
	const IncidenceMap inc = computeIncidence(scene.depth, K, p.edgeJumpMm, p.edgeJumpRel);

	// 2. Mixed pixels: each edge pixel mixes with its neighbour across the
	// largest depth gap (a neighbour with no surface returns nothing and
	// leaves the depth alone).
	const RandomField coverage = whiteNoiseField(W, H, rng);
	std::vector<float> z(N, 0.0f);
	std::vector<uint8_t> invalid(N, 0);
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			const size_t i = idx(x, y);
			const float own = scene.depth.at(x, y);
			z[i] = own;
			if (own <= 0.0f || !inc.edge[i])
				continue;
			const double jump = std::max(p.edgeJumpMm, p.edgeJumpRel * own);
			float other = 0.0f;
			double gap = jump;
			for (int dy = -1; dy <= 1; ++dy) {
				for (int dx = -1; dx <= 1; ++dx) {
					const int nx = x + dx, ny = y + dy;
					if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= W || ny >= H)
						continue;
					const float zn = scene.depth.at(nx, ny);
					if (zn > 0.0f && std::abs(zn - own) > gap) {
						gap = std::abs(zn - own);
						other = zn;
					}
				}
			}
			if (other <= 0.0f)
				continue;
			// One uniform draw decides both the filter and the coverage.
			const double u = normalCdf(coverage.values[i]);
			if (u < p.flyingInvalid) {
				invalid[i] = 1;
				continue;
			}
			const double c = p.ownCoverageMin + (1.0 - p.ownCoverageMin) *
								    (u - p.flyingInvalid) / (1.0 - p.flyingInvalid);
			z[i] = static_cast<float>(tofMixedDepth(own, other, c));
		}
	}

	// 3.-5. Noise, wiggling and the amplitude limit.
	const RandomField white = whiteNoiseField(W, H, rng);
	const RandomField lost = correlatedUniformField(W, H, 1, rng);
	const RandomField material = correlatedUniformField(W, H, 3, rng);
	const double phase = rng.uniform(0.0, 2.0 * std::numbers::pi);
	DepthImage16 result(W, H, 0);
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			const size_t i = idx(x, y);
			if (z[i] <= 0.0f || invalid[i])
				continue;
			// Dark or shiny patches return too little light, in blobs.
			if (!scene.label.empty()) {
				const uint16_t l = scene.label.at(x, y);
				if (l < scene.labelDropout.size() && material.values[i] < scene.labelDropout[l])
					continue;
			}
			const double theta = inc.angle[i];
			const double zi = z[i];
			const double amplitude = std::cos(theta) * (p.zRefMm / zi) * (p.zRefMm / zi);
			if (amplitude < p.minAmplitude)
				continue;
			if (amplitude < p.minAmplitude + p.amplitudeSoft) {
				const double f = 1.0 - (amplitude - p.minAmplitude) / p.amplitudeSoft;
				if (lost.values[i] < f * f)
					continue;
			}
			const double v = zi + tofAxialSigmaMm(p, zi, theta) * white.values[i] +
					 p.wiggleMm * std::sin(2.0 * std::numbers::pi * zi / p.wigglePeriodMm + phase);
			result.at(x, y) = sensorDepthValue(v, p.minRangeMm, p.maxRangeMm, p.pixelDropout, rng,
							   depthScale);
		}
	}
	return result;
}

} // namespace ihf
