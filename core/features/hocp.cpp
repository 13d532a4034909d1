// SPDX-License-Identifier: MIT

#include "core/features/hocp.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace ihf {

namespace {

constexpr float kTinyRadius = 1e-12f;

int clampBin(float t, int n)
{
	const int b = static_cast<int>(std::floor(t));
	return std::clamp(b, 0, n - 1);
}

int angularBin(const Eigen::Vector3f &rel, float r, const HocpConfig &cfg)
{
	const float cosTheta = r > kTinyRadius ? rel.z() / r : 1.0f;
	const int it = clampBin(0.5f * (cosTheta + 1.0f) * static_cast<float>(cfg.nTheta), cfg.nTheta);
	// atan2 in double: glibc's atan2f rounds differently on aarch64 than on
	// amd64 (its double atan2 agrees), which would move points across bins.
	const float phi = static_cast<float>(
		std::atan2(static_cast<double>(rel.y()), static_cast<double>(rel.x())));
	const int ip = clampBin((phi + std::numbers::pi_v<float>) * (0.5f / std::numbers::pi_v<float>) *
					static_cast<float>(cfg.nPhi),
				cfg.nPhi);
	return it * cfg.nPhi + ip;
}

float binValue(float weight, HocpWeighting w)
{
	return w == HocpWeighting::kAbsWeight ? std::abs(weight) : 1.0f;
}

// The sum of squares in four lanes combined in one fixed order (a single
// running sum is one dependent add per bin). With count weighting every
// term is a whole number and the sum exact in any order.
void normalise(std::span<float> out)
{
	double lane[4] = {};
	size_t i = 0;
	for (; i + 4 <= out.size(); i += 4)
		for (size_t l = 0; l < 4; ++l)
			lane[l] += static_cast<double>(out[i + l]) * out[i + l];
	double s = (lane[0] + lane[2]) + (lane[1] + lane[3]);
	for (; i < out.size(); ++i)
		s += static_cast<double>(out[i]) * out[i];
	if (s <= 0.0)
		return;
	const float inv = static_cast<float>(1.0 / std::sqrt(s));
	for (float &v : out)
		v *= inv;
}

// Shared body: keep(i) decides which points count.
template<typename Keep>
int histogram(std::span<const PartCp> cps, const HocpConfig &cfg, std::span<float> out, Keep keep)
{
	const int dim = hocpDimension(cfg);
	const int nAng = cfg.nTheta * cfg.nPhi;
	assert(out.size() >= static_cast<size_t>(dim));
	std::fill_n(out.begin(), dim, 0.0f);

	float maxLogR = -std::numeric_limits<float>::infinity();
	int kept = 0;
	for (const PartCp &c : cps)
		if (keep(c)) {
			maxLogR = std::max(maxLogR, c.logR);
			++kept;
		}
	if (kept == 0)
		return 0;

	// t_r = nR (log r - log r_min) / (log r_max - log r_min), r_min = f r_max.
	const float logFrac = std::log(cfg.rMinFraction);
	const float logRMin = maxLogR + logFrac;
	const float rScale = static_cast<float>(cfg.nR) / -logFrac;
	const bool split = cfg.weighting == HocpWeighting::kSignSplit;
	const int d = cfg.nR * nAng;
	for (const PartCp &c : cps) {
		if (!keep(c))
			continue;
		const int ir = clampBin((c.logR - logRMin) * rScale, cfg.nR);
		int bin = ir * nAng + c.angBin;
		if (split && c.weight < 0.0f)
			bin += d;
		out[bin] += binValue(c.weight, cfg.weighting);
	}
	normalise(out.first(dim));
	return kept;
}

} // namespace

int hocpDimension(const HocpConfig &cfg)
{
	const int d = cfg.nR * cfg.nTheta * cfg.nPhi;
	return cfg.weighting == HocpWeighting::kSignSplit ? 2 * d : d;
}

std::string hocpBinsProblem(const HocpConfig &cfg)
{
	if (cfg.nR < 1 || cfg.nTheta < 1 || cfg.nPhi < 1)
		return "bin counts n_r " + std::to_string(cfg.nR) + ", n_theta " + std::to_string(cfg.nTheta) +
		       ", n_phi " + std::to_string(cfg.nPhi) + " must each be at least 1";
	const int64_t angular = int64_t{cfg.nTheta} * cfg.nPhi;
	const int64_t dim = angular * cfg.nR * (cfg.weighting == HocpWeighting::kSignSplit ? 2 : 1);
	if (angular > int64_t{std::numeric_limits<uint16_t>::max()} + 1 || dim > kMaxHocpDimension)
		return "bin counts n_r " + std::to_string(cfg.nR) + " x n_theta " + std::to_string(cfg.nTheta) +
		       " x n_phi " + std::to_string(cfg.nPhi) + " give " + std::to_string(dim) +
		       " dimensions, more than the " + std::to_string(kMaxHocpDimension) + " allowed";
	return {};
}

void setHocpKeys(std::span<PartCp> cps, const HocpConfig &cfg)
{
	for (PartCp &c : cps) {
		const float r = c.rel.norm();
		c.logR = std::log(std::max(r, kTinyRadius));
		c.angBin = static_cast<uint16_t>(angularBin(c.rel, r, cfg));
	}
}

int computeHocp(std::span<const PartCp> cps, const HocpConfig &cfg, std::span<float> out)
{
	return histogram(cps, cfg, out, [](const PartCp &) { return true; });
}

int computeHocpDepthChecked(std::span<const PartCp> cps, float zMin, float zMax, float margin,
			    const HocpConfig &cfg, std::span<float> out)
{
	const float lo = zMin - margin, hi = zMax + margin;
	return histogram(cps, cfg, out, [lo, hi](const PartCp &c) {
		return c.rel.z() >= lo && c.rel.z() <= hi;
	});
}

int computeHocpReference(std::span<const PartCp> cps, const HocpConfig &cfg, std::span<float> out)
{
	const int dim = hocpDimension(cfg);
	assert(out.size() >= static_cast<size_t>(dim));
	std::fill_n(out.begin(), dim, 0.0f);
	if (cps.empty())
		return 0;
	float rMax = 0.0f;
	for (const PartCp &c : cps)
		rMax = std::max(rMax, c.rel.norm());
	const float rMin = cfg.rMinFraction * rMax;
	const int nAng = cfg.nTheta * cfg.nPhi;
	const int d = cfg.nR * nAng;
	for (const PartCp &c : cps) {
		const float r = c.rel.norm();
		const float tr = r > kTinyRadius && rMin > 0.0f
					 ? static_cast<float>(cfg.nR) * std::log(r / rMin) / std::log(rMax / rMin)
					 : 0.0f;
		int bin = clampBin(tr, cfg.nR) * nAng + angularBin(c.rel, r, cfg);
		if (cfg.weighting == HocpWeighting::kSignSplit && c.weight < 0.0f)
			bin += d;
		out[bin] += binValue(c.weight, cfg.weighting);
	}
	normalise(out.first(dim));
	return static_cast<int>(cps.size());
}

float hocpDistanceSquared(std::span<const float> a, std::span<const float> b)
{
	float s = 0.0f;
	const size_t n = std::min(a.size(), b.size());
	for (size_t i = 0; i < n; ++i) {
		const float d = a[i] - b[i];
		s += d * d;
	}
	return s;
}

} // namespace ihf
