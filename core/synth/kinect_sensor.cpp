// SPDX-License-Identifier: MIT
#include "core/synth/kinect_sensor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/synth/projector_shadow.h"
#include "core/synth/random_field.h"
#include "core/synth/sensor_output.h"
#include "core/synth/surface_incidence.h"

namespace ihf {

namespace {

constexpr double kHalfPi = std::numbers::pi / 2;

// Keeps the grazing terms finite; such pixels are dropped anyway.
double clampAngle(double theta) { return std::clamp(theta, 0.0, kHalfPi - 0.02); }

} // namespace

double kinectAxialSigmaMm(const KinectParams &p, double zMm, double theta)
{
	const double z = zMm * 1e-3;
	double s = p.axialA + p.axialB * (z - p.axialZ0) * (z - p.axialZ0);
	theta = clampAngle(theta);
	if (theta > std::numbers::pi / 3) {
		const double r = theta / (kHalfPi - theta);
		s += p.axialGrazing / std::sqrt(std::max(z, 1e-3)) * r * r;
	}
	return s * 1e3;
}

double kinectQuantise(const KinectParams &p, double zMm)
{
	const double bf = p.baselineMm * p.focalPx;
	const double d = std::round(bf / zMm * p.subpixel) / p.subpixel;
	return d > 0 ? bf / d : 0.0;
}

double kinectDepthStep(const KinectParams &p, double zMm)
{
	return zMm * zMm / (p.baselineMm * p.focalPx * p.subpixel);
}

DepthImage16 simulateKinect(const SensorScene &scene, const CameraIntrinsics &K,
			    const KinectParams &p, SynthRandom &rng, double depthScale)
{
	const int W = scene.depth.width, H = scene.depth.height;
	const size_t N = static_cast<size_t>(W) * H;
	auto idx = [W](int x, int y) { return static_cast<size_t>(y) * W + x; };

	const IncidenceMap inc = computeIncidence(scene.depth, K, p.edgeJumpMm, p.edgeJumpRel);
	std::vector<uint8_t> shadow(N, 0);
	if (!scene.projector.empty())
		shadow = projectorShadow(scene.depth, scene.projector, scene.projectorX0, K,
					 p.baselineMm, p.shadowToleranceMm);

	// 2. Lateral jitter: resample everything per-pixel at displaced spots.
	const RandomField jx = correlatedNormalField(W, H, p.lateralRadius, rng);
	const RandomField jy = correlatedNormalField(W, H, p.lateralRadius, rng);
	std::vector<float> z(N), theta(N);
	std::vector<uint16_t> label(N, 0);
	std::vector<uint8_t> lit(N), edge(N);
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			const double t = clampAngle(inc.angleAt(x, y));
			const double sl = std::min(p.lateralPx + p.lateralGrazing * t / (kHalfPi - t), 3.0);
			const int sx = std::clamp(x + static_cast<int>(std::lround(sl * jx.at(x, y))), 0, W - 1);
			const int sy = std::clamp(y + static_cast<int>(std::lround(sl * jy.at(x, y))), 0, H - 1);
			const size_t i = idx(x, y), s = idx(sx, sy);
			z[i] = scene.depth.at(sx, sy);
			theta[i] = inc.angle[s];
			edge[i] = inc.edge[s];
			lit[i] = z[i] > 0.0f && !shadow[s];
			if (!scene.label.empty())
				label[i] = scene.label.at(sx, sy);
		}
	}

	// 3. Foreground fattening: a nearer lit surface within the bleed radius
	// takes the pixel over (also over shadow: the silhouette grows first).
	const RandomField fat = correlatedUniformField(W, H, 2, rng);
	{
		std::vector<float> z2 = z, t2 = theta;
		std::vector<uint16_t> l2 = label;
		std::vector<uint8_t> lit2 = lit;
		for (int y = 0; y < H; ++y) {
			for (int x = 0; x < W; ++x) {
				const int r = std::min(2, static_cast<int>(fat.at(x, y) * 2.0 * p.fatteningPx + 0.5));
				if (r == 0)
					continue;
				const size_t i = idx(x, y);
				const float own = lit[i] ? z[i] : std::numeric_limits<float>::max();
				float best = own;
				size_t from = i;
				for (int dy = -r; dy <= r; ++dy) {
					for (int dx = -r; dx <= r; ++dx) {
						const int nx = x + dx, ny = y + dy;
						if (nx < 0 || ny < 0 || nx >= W || ny >= H)
							continue;
						const size_t j = idx(nx, ny);
						if (lit[j] && z[j] < best) {
							best = z[j];
							from = j;
						}
					}
				}
				if (from == i)
					continue;
				const double jump = std::max(p.edgeJumpMm, p.edgeJumpRel * best);
				if (own - best <= jump)
					continue;
				z2[i] = z[from];
				t2[i] = theta[from];
				l2[i] = label[from];
				lit2[i] = 1;
			}
		}
		z.swap(z2);
		theta.swap(t2);
		label.swap(l2);
		lit.swap(lit2);
	}

	// 4.-5. Axial noise (correlated + white) and disparity quantisation.
	const RandomField white = whiteNoiseField(W, H, rng);
	const RandomField corr = correlatedNormalField(W, H, p.noiseRadius, rng);
	const float wc = static_cast<float>(std::sqrt(p.noiseCorrelation));
	const float ww = static_cast<float>(std::sqrt(1.0 - p.noiseCorrelation));
	std::vector<float> out(N, 0.0f);
	for (size_t i = 0; i < N; ++i) {
		if (!lit[i])
			continue;
		const double sigma = kinectAxialSigmaMm(p, z[i], theta[i]);
		// The quantisation adds step^2/12 of variance: add only the rest.
		const double step = kinectDepthStep(p, z[i]);
		const double sg = std::sqrt(std::max(sigma * sigma - step * step / 12.0,
						     0.09 * sigma * sigma));
		const double n = wc * corr.values[i] + ww * white.values[i];
		out[i] = static_cast<float>(kinectQuantise(p, z[i] + sg * n));
	}

	// 6. Missing depth.
	const RandomField grazeField = correlatedUniformField(W, H, 2, rng);
	const RandomField edgeField = correlatedUniformField(W, H, 1, rng);
	const RandomField matField = correlatedUniformField(W, H, 3, rng);
	const double maxInc = p.maxIncidenceDeg * std::numbers::pi / 180.0;
	const double soft = p.incidenceSoftDeg * std::numbers::pi / 180.0;
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			const size_t i = idx(x, y);
			if (out[i] <= 0.0f)
				continue;
			bool drop = false;
			const double t = theta[i];
			if (t >= maxInc) {
				drop = true;
			} else if (t > maxInc - soft) {
				const double f = (t - (maxInc - soft)) / soft;
				drop = grazeField.values[i] < f * f;
			}
			// Edge pixels, widened by one column: the matcher fails there.
			const bool nearEdge = edge[i] || (x > 0 && edge[i - 1]) || (x + 1 < W && edge[i + 1]);
			if (nearEdge && edgeField.values[i] < p.edgeDropout)
				drop = true;
			const uint16_t l = label[i];
			if (l < scene.labelDropout.size() && matField.values[i] < scene.labelDropout[l])
				drop = true;
			if (drop)
				out[i] = 0.0f;
		}
	}
	// Small holes of irregular outline: a disc whose radius varies with the
	// edge field's blobs.
	const int blobs = static_cast<int>(p.blobsPerImage * rng.uniform(0.5, 1.5));
	for (int b = 0; b < blobs; ++b) {
		const double cx = rng.uniform(0, W), cy = rng.uniform(0, H);
		const double r = rng.uniform(0.7, p.blobRadiusMax);
		const int reach = static_cast<int>(std::ceil(1.3 * r));
		for (int y = std::max(0, static_cast<int>(cy) - reach); y <= std::min(H - 1, static_cast<int>(cy) + reach); ++y) {
			for (int x = std::max(0, static_cast<int>(cx) - reach); x <= std::min(W - 1, static_cast<int>(cx) + reach); ++x) {
				const double re = r * (0.6 + 0.7 * matField.at(x, y));
				if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= re * re)
					out[idx(x, y)] = 0.0f;
			}
		}
	}
	const int band = rng.uniformInt(p.leftBandMin, std::max(p.leftBandMin, p.leftBandMax));
	for (int y = 0; y < H; ++y) {
		const int w = band + (rng.chance(0.5) ? 1 : 0);
		for (int x = 0; x < std::min(w, W); ++x)
			out[idx(x, y)] = 0.0f;
	}

	DepthImage16 result(W, H, 0);
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			result.at(x, y) = sensorDepthValue(out[idx(x, y)], p.minRangeMm, p.maxRangeMm,
							   p.pixelDropout, rng, depthScale);
		}
	}
	return result;
}

} // namespace ihf
