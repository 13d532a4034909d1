// SPDX-License-Identifier: MIT
// Set-up of the 3L system (constraints, active set) and evaluation; the two
// solvers live in ibs_cg.cpp and ibs_mba.cpp.

#include "core/ibs/ibs_fitter.h"

#include <algorithm>
#include <limits>

namespace ihf {

template<typename A>
bool IbsFitter::carve(A &arena, const IbsLimits &limits)
{
	const size_t maxN = static_cast<size_t>(std::max(limits.maxN, 4));
	const size_t constraints = 3 * static_cast<size_t>(std::max(limits.maxPoints, 0));
	const size_t active = static_cast<size_t>(std::max(limits.maxActive, 0));
	// The coarsest-but-one level has at most ceil(C / 2) cells.
	const size_t coarseNodes = (maxN - 3 + 1) / 2 + 3;
	const size_t coarse = coarseNodes * coarseNodes * coarseNodes;
	bool ok = arenaTake(arena, map_, maxN * maxN * maxN) &&
		  arenaTake(arena, constraints_, constraints) &&
		  arenaTake(arena, residual_, constraints) && arenaTake(arena, active_, active) &&
		  arenaTake(arena, neighbours_, 6 * active);
	for (auto *v : {&x_, &r_, &z_, &p_, &q_, &diag_})
		ok = ok && arenaTake(arena, *v, active);
	// One thread walks all constraints and needs no list.
	const size_t threads = static_cast<size_t>(std::clamp(limits.threads, 1, WorkerPool::kMaxThreads));
	const size_t lists = threads > 1 ? threads * constraints : 0;
	return ok && arenaTake(arena, coarseNum_, coarse) && arenaTake(arena, coarseDen_, coarse) &&
	       arenaTake(arena, shareLists_, lists) && arenaTake(arena, planeCounts_, maxN);
}

size_t IbsFitter::arenaBytes(const IbsLimits &limits)
{
	ArenaSizer sizer;
	IbsFitter scratch;
	scratch.carve(sizer, limits);
	return sizer.bytes;
}

void IbsFitter::reserve(const IbsLimits &limits)
{
	auto arena = Arena::create(arenaBytes(limits));
	if (!arena) {
		*this = IbsFitter();
		return;
	}
	own_ = std::move(*arena);
	(void)reserve(limits, own_);
}

Status IbsFitter::reserve(const IbsLimits &limits, Arena &arena)
{
	activeCount_ = 0;
	constraintCount_ = 0;
	fitValid_ = false;
	if (!carve(arena, limits)) {
		limits_ = IbsLimits{0, 0, 0};
		map_ = {};
		constraints_ = {};
		return makeError(Errc::kCapacity, "IbsFitter: arena too small for the IbsLimits");
	}
	limits_ = limits;
	std::fill(map_.begin(), map_.end(), -1);
	return {};
}

void IbsFitter::resetMap()
{
	for (int a = 0; a < activeCount_; ++a)
		map_[active_[a]] = -1;
	activeCount_ = 0;
}

void IbsFitter::addConstraint(const Eigen::Vector3f &pos, float value)
{
	Constraint &c = constraints_[constraintCount_++];
	int cell[3];
	float u[3];
	for (int a = 0; a < 3; ++a)
		lattice_.locate(pos[a], cell[a], u[a]);
	cubicBlend(u[0], c.bx);
	cubicBlend(u[1], c.by);
	cubicBlend(u[2], c.bz);
	c.pos = pos;
	c.value = value;
	// The column slots are filled once the active set is known; keep the
	// node index of each column's first node meanwhile.
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m)
			c.column[l * 4 + m] = lattice_.linear(cell[0] + l, cell[1] + m, cell[2]);
}

Status IbsFitter::buildConstraints(std::span<const Eigen::Vector3f> points,
				   std::span<const Eigen::Vector3f> normals,
				   const IbsConfig &cfg, IbsFitStats &stats)
{
	const size_t total = points.size();
	const size_t used = std::min(total, static_cast<size_t>(cfg.maxPoints));
	const float eps = cfg.offsetCells * lattice_.delta();

	constraintCount_ = 0;
	for (size_t s = 0; s < used; ++s) {
		// Uniform subsample: the middle of each of `used` equal runs.
		const size_t idx = (2 * s + 1) * total / (2 * used);
		const Eigen::Vector3f &p = points[idx];
		if (!Lattice::inDomain(p)) {
			++stats.pointsOutside;
			continue;
		}
		++stats.pointsUsed;
		addConstraint(p, 0.0f);
		const Eigen::Vector3f &nrm = normals[idx];
		if (nrm.squaredNorm() < 0.25f)
			continue;
		const Eigen::Vector3f front = p + eps * nrm;
		const Eigen::Vector3f back = p - eps * nrm;
		if (Lattice::inDomain(front))
			addConstraint(front, cfg.offsetValue);
		if (Lattice::inDomain(back))
			addConstraint(back, -cfg.offsetValue);
	}
	stats.constraints = constraintCount_;
	return {};
}

Status IbsFitter::buildActiveSet()
{
	const int cap = static_cast<int>(active_.size());
	int count = 0;
	int32_t first = std::numeric_limits<int32_t>::max(), last = -1;
	for (int ci = 0; ci < constraintCount_; ++ci) {
		const Constraint &c = constraints_[ci];
		for (int col = 0; col < 16; ++col) {
			const int32_t base = c.column[col];
			first = std::min(first, base);
			last = std::max(last, base + 3);
			for (int p = 0; p < 4; ++p) {
				int32_t &slot = map_[base + p];
				if (slot != -1)
					continue;
				if (count == cap) {
					activeCount_ = count; // so resetMap() clears the marks
					return makeError(Errc::kCapacity,
							 "IbsFitter: active control points exceed IbsLimits::maxActive");
				}
				slot = -2;
				active_[count++] = base + p;
			}
		}
	}
	activeCount_ = count;
	// The marked nodes in node order: a scan of their range, not a sort
	// (a sort was ~15 % of a fit from 150 points; the scan makes a fit ~10 %
	// faster, in the same order, so the same bits).
	int a = 0;
	for (int32_t node = first; node <= last; ++node)
		if (map_[node] == -2) {
			map_[node] = a;
			active_[a++] = node;
		}
	for (int ci = 0; ci < constraintCount_; ++ci) {
		Constraint &c = constraints_[ci];
		for (int col = 0; col < 16; ++col)
			c.column[col] = map_[c.column[col]];
	}
	return {};
}

float IbsFitter::constraintValue(const Constraint &c, const float *x) const
{
	// Each column's four nodes are consecutive: one 4-wide vector per column.
	using Vec4 = Eigen::Array4f;
	Vec4 acc = Vec4::Zero();
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m)
			acc += (c.bx[l] * c.by[m]) * Eigen::Map<const Vec4>(x + c.column[l * 4 + m]);
	return (acc * Eigen::Map<const Vec4>(c.bz)).sum();
}

void IbsFitter::scatter(const Constraint &c, float s, float *y) const
{
	using Vec4 = Eigen::Array4f;
	const Vec4 bz = Eigen::Map<const Vec4>(c.bz) * s;
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m)
			Eigen::Map<Vec4>(y + c.column[l * 4 + m]) += (c.bx[l] * c.by[m]) * bz;
}

Expected<IbsFitStats> IbsFitter::fit(std::span<const Eigen::Vector3f> points,
				     std::span<const Eigen::Vector3f> normals,
				     const IbsConfig &cfg, std::span<ControlPoint> out,
				     std::span<const ControlPoint> previous, WorkerPool *pool)
{
	resetMap();
	pool_ = pool;
	fitValid_ = false;
	IbsFitStats stats;

	if (cfg.n < 4 || cfg.n > limits_.maxN)
		return makeError(Errc::kInvalidArgument, "IbsFitter: IbsConfig::n outside 4 .. IbsLimits::maxN");
	if (normals.size() != points.size())
		return makeError(Errc::kInvalidArgument, "IbsFitter: normals and points differ in size");
	if (cfg.maxPoints <= 0 || cfg.maxPoints > limits_.maxPoints)
		return makeError(Errc::kCapacity, "IbsFitter: IbsConfig::maxPoints exceeds IbsLimits::maxPoints");
	if (!(cfg.offsetCells > 0.0f) || !(cfg.offsetValue > 0.0f))
		return makeError(Errc::kInvalidArgument, "IbsFitter: offsetCells and offsetValue must be > 0");

	lattice_ = Lattice(cfg.n);
	if (auto st = buildConstraints(points, normals, cfg, stats); !st)
		return st.error();
	if (constraintCount_ == 0)
		return makeError(Errc::kInvalidArgument, "IbsFitter: no points inside the unit cube");
	if (auto st = buildActiveSet(); !st)
		return st.error();
	stats.activeCount = activeCount_;
	if (out.size() < static_cast<size_t>(activeCount_))
		return makeError(Errc::kCapacity, "IbsFitter: output span smaller than the active set");

	std::fill_n(x_.begin(), activeCount_, 0.0f);
	if (cfg.solver == IbsSolver::kMultilevelBa) {
		solveMba(cfg);
	} else {
		bool warm = false;
		if (cfg.warmStart == IbsWarmStart::kMultilevelBa) {
			solveMba(cfg);
			warm = true;
		} else if (cfg.warmStart == IbsWarmStart::kPrevious && !previous.empty()) {
			// Merge-join two index-sorted lists.
			size_t j = 0;
			for (int a = 0; a < activeCount_; ++a) {
				while (j < previous.size() && previous[j].index < active_[a])
					++j;
				if (j < previous.size() && previous[j].index == active_[a])
					x_[a] = previous[j].weight;
			}
			warm = true;
		}
		solveCg(cfg, warm, stats);
	}

	for (int a = 0; a < activeCount_; ++a)
		out[a] = ControlPoint{active_[a], lattice_.nodePosition(active_[a]), x_[a]};
	fitValid_ = true;
	return stats;
}

float IbsFitter::evaluate(const Eigen::Vector3f &x) const
{
	Eigen::Vector3f g;
	return evaluate(x, g);
}

float IbsFitter::evaluate(const Eigen::Vector3f &x, Eigen::Vector3f &gradient) const
{
	gradient.setZero();
	if (!fitValid_)
		return 0.0f;
	int cell[3];
	float u[3], b[3][4], d[3][4];
	for (int a = 0; a < 3; ++a) {
		lattice_.locate(x[a], cell[a], u[a]);
		cubicBlend(u[a], b[a]);
		cubicBlendDerivative(u[a], d[a]);
	}
	float f = 0.0f;
	Eigen::Vector3f g = Eigen::Vector3f::Zero();
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m)
			for (int p = 0; p < 4; ++p) {
				const int32_t slot =
					map_[lattice_.linear(cell[0] + l, cell[1] + m, cell[2] + p)];
				if (slot < 0)
					continue;
				const float w = x_[slot];
				f += w * b[0][l] * b[1][m] * b[2][p];
				g.x() += w * d[0][l] * b[1][m] * b[2][p];
				g.y() += w * b[0][l] * d[1][m] * b[2][p];
				g.z() += w * b[0][l] * b[1][m] * d[2][p];
			}
	gradient = g * static_cast<float>(lattice_.cells());
	return f;
}

} // namespace ihf
