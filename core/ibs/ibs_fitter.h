// SPDX-License-Identifier: MIT
#pragma once

// Fits an implicit B-spline f (Eq. 3-6) to a point cloud in the unit cube with
// the 3L scheme: f = 0 at each data point p, f = +c at p + eps n and -c at
// p - eps n (n the normal oriented to the camera, so f > 0 in front of the
// surface). Only the active control points, those whose support holds a
// constraint, are unknowns.
//
// Memory is fixed at reserve(): a dense node -> active-slot map of maxN^3
// int32 (4 MB at N = 100; only the entries a fit touched are reset, so it is
// never cleared whole), per-constraint tables for 3 * maxPoints equations and
// per-active arrays for maxActive nodes, and with threads > 1 a constraint
// list per thread. fit() allocates nothing. The
// scratch lives in an arena: the fitter's own, or one shared with the rest of
// the frame path (reserve(limits, arena)).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/ibs/bspline_basis.h"
#include "core/ibs/control_point.h"
#include "core/ibs/ibs_config.h"
#include "core/runtime/arena.h"
#include "core/runtime/worker_pool.h"

namespace ihf {

class IbsFitter
{
public:
	IbsFitter() = default;
	explicit IbsFitter(const IbsLimits &limits) { reserve(limits); }

	// Sizes all scratch for the limits in an arena of the fitter's own
	// (allocates); not per frame.
	void reserve(const IbsLimits &limits);
	// The same, carved from a shared arena (kCapacity if it is too small;
	// the fitter then has no capacity). The arena must outlive the fitter.
	Status reserve(const IbsLimits &limits, Arena &arena);
	// Arena bytes reserve() takes for the limits.
	static size_t arenaBytes(const IbsLimits &limits);
	const IbsLimits &limits() const { return limits_; }
	size_t reservedBytes() const { return arenaBytes(limits_); }

	// Fits points (unit cube) with normals (unit length, or zero when
	// unknown: such points only give f = 0). Writes the active control points
	// sorted by index into out and returns the statistics; kCapacity if out,
	// the reserved points or active set are too small, kInvalidArgument on
	// bad sizes. previous (sorted by index, same lattice) seeds CG when
	// cfg.warmStart is kPrevious. With a pool, CG's products are spread over
	// min(pool threads, IbsLimits::threads) threads; the result is the same
	// bits for any thread count. fit() must then not run inside one of the
	// pool's tasks.
	Expected<IbsFitStats> fit(std::span<const Eigen::Vector3f> points,
				  std::span<const Eigen::Vector3f> normals,
				  const IbsConfig &cfg, std::span<ControlPoint> out,
				  std::span<const ControlPoint> previous = {},
				  WorkerPool *pool = nullptr);

	// f and its gradient (unit-cube units) of the last fit; inactive nodes
	// count as zero.
	float evaluate(const Eigen::Vector3f &x) const;
	float evaluate(const Eigen::Vector3f &x, Eigen::Vector3f &gradient) const;

	const Lattice &lattice() const { return lattice_; }
	int activeCount() const { return activeCount_; }

private:
	// One 3L equation: the value wanted at a position, its blending values
	// and, for each of the 4 x 4 node columns (i + l, j + m), the active slot
	// of node k; nodes k .. k + 3 of a column are consecutive slots because
	// the active set is sorted by index.
	struct Constraint {
		int32_t column[16];
		float bx[4], by[4], bz[4];
		Eigen::Vector3f pos;
		float value;
	};

	template<typename A>
	bool carve(A &arena, const IbsLimits &limits);
	void resetMap();
	void addConstraint(const Eigen::Vector3f &pos, float value);
	Status buildConstraints(std::span<const Eigen::Vector3f> points,
				std::span<const Eigen::Vector3f> normals,
				const IbsConfig &cfg, IbsFitStats &stats);
	Status buildActiveSet();
	float constraintValue(const Constraint &c, const float *x) const;
	void scatter(const Constraint &c, float s, float *y) const;

	// Solvers (ibs_cg.cpp, ibs_mba.cpp); both write x_.
	void solveCg(const IbsConfig &cfg, bool warm, IbsFitStats &stats);
	void solveMba(const IbsConfig &cfg);
	void buildNeighbours();
	void planShares(int shares);
	void applyNormal(const float *p, float *out, float lambdaSmooth, float lambdaRidge);
	void applyNormalShare(int share, const float *p, float *out, float lambdaSmooth,
			      float lambdaRidge) const;

	IbsLimits limits_;
	Lattice lattice_;
	Arena own_; // used by reserve(limits) only

	std::span<int32_t> map_;     // node index -> active slot, -1 if inactive
	std::span<Constraint> constraints_;
	std::span<float> residual_;  // per constraint, multilevel BA
	int constraintCount_ = 0;
	bool fitValid_ = false;

	// Per active slot.
	std::span<int32_t> active_;  // node index, sorted
	std::span<int32_t> neighbours_; // 6 per slot: -x +x -y +y -z +z, -1 if none
	std::span<float> x_, r_, z_, p_, q_, diag_;
	int activeCount_ = 0;

	// CG's product A p split over threads: share s owns the active slots
	// [shareBegin_[s], shareBegin_[s + 1]), whole x-planes of the lattice,
	// and walks the constraints touching them (in order) from its list.
	WorkerPool *pool_ = nullptr; // of the current fit
	int shares_ = 1;
	std::array<int32_t, WorkerPool::kMaxThreads + 1> shareBegin_{};
	std::array<int32_t, WorkerPool::kMaxThreads> shareListSize_{};
	std::span<int32_t> shareLists_;  // IbsLimits::threads lists of 3 * maxPoints
	std::span<int32_t> planeCounts_; // constraints per first x-plane, maxN

	// Dense coarse lattices of the multilevel BA (levels below the finest).
	std::span<float> coarseNum_, coarseDen_;
};

} // namespace ihf
