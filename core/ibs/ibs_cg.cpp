// SPDX-License-Identifier: MIT
// Jacobi-preconditioned conjugate gradients on the regularised normal
// equations (E^T E + ls D^T D + lr I) x = E^T d over the active set. E is
// never formed: each product streams the constraint table once (64 nodes per
// equation), so an iteration costs O(64 * constraints + active). With a pool
// the product is split by lattice x-planes over its threads; the dot products
// and vector updates stay on the calling thread, in slot order.

#include <algorithm>
#include <cmath>

#include "core/ibs/ibs_fitter.h"

namespace ihf {

void IbsFitter::buildNeighbours()
{
	const int n = lattice_.n;
	const int32_t stride[3] = {n * n, n, 1};
	for (int a = 0; a < activeCount_; ++a) {
		int ijk[3];
		lattice_.unpack(active_[a], ijk[0], ijk[1], ijk[2]);
		int32_t *nb = &neighbours_[6 * static_cast<size_t>(a)];
		for (int axis = 0; axis < 3; ++axis) {
			nb[2 * axis] = ijk[axis] > 0 ? map_[active_[a] - stride[axis]] : -1;
			nb[2 * axis + 1] = ijk[axis] < n - 1 ? map_[active_[a] + stride[axis]] : -1;
		}
	}
}

// Splits the active slots into `shares` ranges of whole x-planes holding
// about equal numbers of constraints (a constraint's 64 nodes lie on its
// first plane and the three after it), and lists for each range the
// constraints that touch it, in order. A 4-node column lies on one plane, so
// it falls wholly inside one range.
void IbsFitter::planShares(int shares)
{
	const int n = lattice_.n;
	shares = std::clamp(shares, 1, static_cast<int>(shareListSize_.size()));
	if (shares > 1 && shareLists_.size() < static_cast<size_t>(shares) * constraintCount_)
		shares = 1;
	shares_ = shares;
	shareBegin_[0] = 0;
	shareBegin_[static_cast<size_t>(shares)] = activeCount_;
	if (shares == 1)
		return;

	std::fill_n(planeCounts_.begin(), n, 0);
	for (int ci = 0; ci < constraintCount_; ++ci)
		++planeCounts_[active_[constraints_[ci].column[0]] / (n * n)];
	int plane = 0;
	int64_t below = 0; // constraints whose first plane is below `plane`
	for (int s = 1; s < shares; ++s) {
		const int64_t target = static_cast<int64_t>(constraintCount_) * s / shares;
		while (plane < n && below < target)
			below += planeCounts_[plane++];
		const int32_t firstNode = plane * n * n;
		shareBegin_[static_cast<size_t>(s)] = static_cast<int32_t>(
			std::lower_bound(active_.begin(), active_.begin() + activeCount_, firstNode) -
			active_.begin());
	}

	for (int s = 0; s < shares; ++s) {
		const int32_t begin = shareBegin_[static_cast<size_t>(s)];
		const int32_t end = shareBegin_[static_cast<size_t>(s) + 1];
		int32_t *list = shareLists_.data() + static_cast<size_t>(s) * constraintCount_;
		int32_t size = 0;
		for (int ci = 0; ci < constraintCount_; ++ci) {
			const Constraint &c = constraints_[ci];
			if (c.column[0] < end && c.column[15] + 3 >= begin)
				list[size++] = ci;
		}
		shareListSize_[static_cast<size_t>(s)] = size;
	}
}

void IbsFitter::applyNormal(const float *p, float *out, float lambdaSmooth, float lambdaRidge)
{
	if (shares_ == 1 || pool_ == nullptr) {
		for (int s = 0; s < shares_; ++s)
			applyNormalShare(s, p, out, lambdaSmooth, lambdaRidge);
		return;
	}
	pool_->run(shares_, [&](int s, int) { applyNormalShare(s, p, out, lambdaSmooth, lambdaRidge); });
}

// out = A p on one share's slots. Every out[x] receives its terms in the
// order of the one-pass form (constraints in order, then the smoothness
// terms of slots a = x - n^2, x - n, x - 1, x, x + 1, x + n, x + n^2, as a
// loop over a scattering its three-point stencils would add them): the
// same bits for any split.
void IbsFitter::applyNormalShare(int share, const float *p, float *out, float lambdaSmooth,
				 float lambdaRidge) const
{
	const int32_t begin = shareBegin_[static_cast<size_t>(share)];
	const int32_t end = shareBegin_[static_cast<size_t>(share) + 1];
	std::fill(out + begin, out + end, 0.0f);
	using Vec4 = Eigen::Array4f;
	const auto add = [&](const Constraint &c) {
		const Vec4 bz = Eigen::Map<const Vec4>(c.bz) * constraintValue(c, p);
		for (int l = 0; l < 4; ++l)
			for (int m = 0; m < 4; ++m) {
				const int32_t col = c.column[l * 4 + m];
				if (col >= begin && col < end)
					Eigen::Map<Vec4>(out + col) += (c.bx[l] * c.by[m]) * bz;
			}
	};
	if (shares_ == 1) {
		for (int ci = 0; ci < constraintCount_; ++ci)
			add(constraints_[ci]);
	} else {
		const int32_t *list = shareLists_.data() + static_cast<size_t>(share) * constraintCount_;
		for (int32_t k = 0; k < shareListSize_[static_cast<size_t>(share)]; ++k)
			add(constraints_[list[k]]);
	}

	// The second difference at slot a along an axis, if a has both neighbours.
	const auto second = [&](int32_t a, int axis, float &d) {
		const int32_t *nb = &neighbours_[6 * static_cast<size_t>(a)];
		const int32_t lo = nb[2 * axis], hi = nb[2 * axis + 1];
		if (lo < 0 || hi < 0)
			return false;
		d = lambdaSmooth * (p[lo] - 2.0f * p[a] + p[hi]);
		return true;
	};
	for (int32_t x = begin; x < end; ++x) {
		const int32_t *nb = &neighbours_[6 * static_cast<size_t>(x)];
		float acc = out[x];
		float d;
		for (int axis = 0; axis < 3; ++axis) // lower neighbours, x - n^2 first
			if (nb[2 * axis] >= 0 && second(nb[2 * axis], axis, d))
				acc += d;
		for (int axis = 0; axis < 3; ++axis)
			if (second(x, axis, d))
				acc -= 2.0f * d;
		acc += lambdaRidge * p[x];
		for (int axis = 2; axis >= 0; --axis) // upper neighbours, x + 1 first
			if (nb[2 * axis + 1] >= 0 && second(nb[2 * axis + 1], axis, d))
				acc += d;
		out[x] = acc;
	}
}

static double dot(const float *a, const float *b, int count)
{
	double s = 0.0;
	for (int i = 0; i < count; ++i)
		s += static_cast<double>(a[i]) * b[i];
	return s;
}

void IbsFitter::solveCg(const IbsConfig &cfg, bool warm, IbsFitStats &stats)
{
	const int count = activeCount_;
	float *x = x_.data(), *r = r_.data(), *z = z_.data(), *p = p_.data(),
	      *q = q_.data(), *diag = diag_.data();

	buildNeighbours();
	planShares(pool_ ? std::min(pool_->threads(), limits_.threads) : 1);

	// Diagonal of E^T E, whose mean scales the regularisers.
	std::fill_n(diag, count, 0.0f);
	for (int ci = 0; ci < constraintCount_; ++ci) {
		const Constraint &c = constraints_[ci];
		for (int l = 0; l < 4; ++l)
			for (int m = 0; m < 4; ++m) {
				const float w2 = c.bx[l] * c.bx[l] * c.by[m] * c.by[m];
				float *d = diag + c.column[l * 4 + m];
				for (int k = 0; k < 4; ++k)
					d[k] += w2 * c.bz[k] * c.bz[k];
			}
	}
	double mean = 0.0;
	for (int a = 0; a < count; ++a)
		mean += diag[a];
	mean /= std::max(count, 1);
	const float ls = static_cast<float>(cfg.smoothness * mean);
	const float lr = static_cast<float>(cfg.ridge * mean);
	for (int a = 0; a < count; ++a) {
		const int32_t *nb = &neighbours_[6 * static_cast<size_t>(a)];
		for (int axis = 0; axis < 3; ++axis) {
			if (nb[2 * axis] < 0 || nb[2 * axis + 1] < 0)
				continue;
			diag[nb[2 * axis]] += ls;
			diag[a] += 4.0f * ls;
			diag[nb[2 * axis + 1]] += ls;
		}
	}
	for (int a = 0; a < count; ++a)
		diag[a] = 1.0f / (diag[a] + lr);

	// r = b - A x with b = E^T d.
	std::fill_n(r, count, 0.0f);
	for (int ci = 0; ci < constraintCount_; ++ci)
		scatter(constraints_[ci], constraints_[ci].value, r);
	const double bNorm = std::sqrt(dot(r, r, count));
	if (warm) {
		applyNormal(x, q, ls, lr);
		for (int a = 0; a < count; ++a)
			r[a] -= q[a];
	}

	for (int a = 0; a < count; ++a)
		p[a] = z[a] = diag[a] * r[a];
	double rz = dot(r, z, count);
	double rNorm = std::sqrt(dot(r, r, count));
	int it = 0;
	const double target = cfg.cgTolerance * bNorm;
	for (; it < cfg.cgMaxIterations && rNorm > target; ++it) {
		applyNormal(p, q, ls, lr);
		const double pq = dot(p, q, count);
		if (!(pq > 0.0))
			break;
		const float alpha = static_cast<float>(rz / pq);
		// r.z and r.r summed in the one pass, each in slot order as dot()
		// would: two independent chains instead of two latency-bound loops.
		double rzNew = 0.0, rr = 0.0;
		for (int a = 0; a < count; ++a) {
			x[a] += alpha * p[a];
			r[a] -= alpha * q[a];
			z[a] = diag[a] * r[a];
			rzNew += static_cast<double>(r[a]) * z[a];
			rr += static_cast<double>(r[a]) * r[a];
		}
		const float beta = static_cast<float>(rzNew / rz);
		rz = rzNew;
		for (int a = 0; a < count; ++a)
			p[a] = z[a] + beta * p[a];
		rNorm = std::sqrt(rr);
	}
	stats.iterations = it;
	stats.relResidual = bNorm > 0.0 ? static_cast<float>(rNorm / bNorm) : 0.0f;
}

} // namespace ihf
