// SPDX-License-Identifier: MIT
#pragma once

// Settings of the implicit B-spline fit (3L, Blane et al. 2000) and the
// capacities a fitter reserves once.

#include <cstdint>

namespace ihf {

enum class IbsSolver : uint8_t {
	kConjugateGradient, // regularised least squares, bounded iterations
	kMultilevelBa,      // Lee-Wolberg-Shin multilevel B-spline approximation
};

// Initial guess of the conjugate-gradient solver.
enum class IbsWarmStart : uint8_t {
	kZero,
	kMultilevelBa, // the multilevel BA solution, then CG polishes it
	kPrevious,     // the control points passed to fit() (same lattice)
};

struct IbsConfig {
	int n = 50;                    // lattice nodes per axis (paper: 50 .. 100)
	IbsSolver solver = IbsSolver::kConjugateGradient;
	float offsetCells = 0.5f;      // 3L offset epsilon, in lattice cells
	float offsetValue = 1.0f;      // 3L value c at p +/- epsilon n
	int maxPoints = 3000;          // data points used (uniform subsample)

	// Conjugate gradients on the normal equations over the active set. A
	// multilevel-BA warm start gained less than its cost in iterations on
	// LM-O crops (bench_ibs), hence a cold start by default.
	IbsWarmStart warmStart = IbsWarmStart::kZero;
	int cgMaxIterations = 30;
	float cgTolerance = 1e-3f;     // stop at |r| <= tol |b|
	// Regularisers, relative to the mean diagonal of E^T E: second
	// differences of the control values along each axis (thin-plate like,
	// zero for a linear ramp) and a ridge that keeps the system definite.
	float smoothness = 0.05f;
	float ridge = 1e-3f;

	// Multilevel BA: number of levels, each coarser one halving the cells.
	int mbaLevels = 3;
};

struct IbsLimits {
	int maxN = 100;
	int maxPoints = 4000;
	int maxActive = 100000; // active control points of one fit
	// Threads a fit may spread its CG products over (fit()'s pool): each
	// takes a list of up to 3 * maxPoints constraint indices.
	int threads = 1;
};

struct IbsFitStats {
	int pointsUsed = 0;     // data points after subsampling and domain check
	int pointsOutside = 0;  // subsampled points outside the unit cube, skipped
	int constraints = 0;    // 3L equations
	int activeCount = 0;    // active control points
	int iterations = 0;     // CG iterations run (0 for BA)
	float relResidual = 0;  // CG: |r| / |b| at exit
};

} // namespace ihf
