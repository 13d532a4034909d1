// SPDX-License-Identifier: MIT
#pragma once

// Histogram of Control Points (Sect. III-A): a spherical histogram of a
// part's control points around the part centre,
//   t_r     = nu_r log(r / r_min) / log(r_max / r_min),
//   t_theta = nu_theta (z / r + 1) / 2   (cosine of the inclination),
//   t_phi   = nu_phi (atan2(y, x) + pi) / (2 pi),
// with r_max the distance of the farthest counted control point and
// r_min = rMinFraction r_max (closer points fall in the first radial bin).
// Bin (ir, it, ip) sits at (ir nu_theta + it) nu_phi + ip; with kSignSplit
// the negative-weight points use a second block of d bins. The histogram is
// L2-normalised (all zero when nothing is counted). Everything is relative to
// the centre, so translation cannot change it.

#include <cstdint>
#include <span>
#include <string>

#include "core/features/part.h"

namespace ihf {

enum class HocpWeighting : uint8_t {
	kCount,     // the paper: one per control point
	kAbsWeight, // |weight| per control point
	kSignSplit, // counts, separate histograms for weight >= 0 and < 0
};

struct HocpConfig {
	int nR = 4;
	int nTheta = 8;
	int nPhi = 8;
	float rMinFraction = 0.05f;
	HocpWeighting weighting = HocpWeighting::kCount;
};

// Length of the feature vector: nR nTheta nPhi, twice that for kSignSplit.
// Only for bin counts hocpBinsProblem() accepts.
int hocpDimension(const HocpConfig &cfg);

// The longest descriptor accepted; the defaults have 256 bins.
inline constexpr int kMaxHocpDimension = 1 << 16;

// Empty when the bin counts are usable: each at least 1, the angular bins
// numbered in 16 bits (PartCp::angBin) and hocpDimension() at most
// kMaxHocpDimension. Otherwise what is wrong, for readers of files and
// configurations to report.
std::string hocpBinsProblem(const HocpConfig &cfg);

// Fills logR and angBin of each control point from rel.
void setHocpKeys(std::span<PartCp> cps, const HocpConfig &cfg);

// HoCP of all cps (keys must be set) into out (hocpDimension entries).
// Returns the number of control points counted.
int computeHocp(std::span<const PartCp> cps, const HocpConfig &cfg, std::span<float> out);

// The forest's depth check: counts only the control points whose relative
// depth lies in [zMin - margin, zMax + margin] (a template part's range), so
// occluders in front and background behind the template's extent drop out.
// r_max is taken over the kept points. Returns the number kept.
int computeHocpDepthChecked(std::span<const PartCp> cps, float zMin, float zMax, float margin,
			    const HocpConfig &cfg, std::span<float> out);

// The same histogram computed straight from rel with the paper's formulas,
// without the precomputed keys; for checks and offline tools.
int computeHocpReference(std::span<const PartCp> cps, const HocpConfig &cfg, std::span<float> out);

// Squared L2 distance of two histograms of the same length.
float hocpDistanceSquared(std::span<const float> a, std::span<const float> b);

} // namespace ihf
