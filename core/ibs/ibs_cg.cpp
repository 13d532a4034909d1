// SPDX-License-Identifier: MIT
// Jacobi-preconditioned conjugate gradients on the regularised normal
// equations (E^T E + ls D^T D + lr I) x = E^T d over the active set. E is
// never formed: each product streams the constraint table once (64 nodes per
// equation), so an iteration costs O(64 * constraints + active).

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

void IbsFitter::applyNormal(const float *p, float *out, float lambdaSmooth,
			    float lambdaRidge) const
{
	std::fill_n(out, activeCount_, 0.0f);
	for (int ci = 0; ci < constraintCount_; ++ci) {
		const Constraint &c = constraints_[ci];
		scatter(c, constraintValue(c, p), out);
	}
	for (int a = 0; a < activeCount_; ++a) {
		const int32_t *nb = &neighbours_[6 * static_cast<size_t>(a)];
		for (int axis = 0; axis < 3; ++axis) {
			const int32_t lo = nb[2 * axis], hi = nb[2 * axis + 1];
			if (lo < 0 || hi < 0)
				continue;
			const float d = lambdaSmooth * (p[lo] - 2.0f * p[a] + p[hi]);
			out[lo] += d;
			out[a] -= 2.0f * d;
			out[hi] += d;
		}
		out[a] += lambdaRidge * p[a];
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
		for (int a = 0; a < count; ++a) {
			x[a] += alpha * p[a];
			r[a] -= alpha * q[a];
			z[a] = diag[a] * r[a];
		}
		const double rzNew = dot(r, z, count);
		const float beta = static_cast<float>(rzNew / rz);
		rz = rzNew;
		for (int a = 0; a < count; ++a)
			p[a] = z[a] + beta * p[a];
		rNorm = std::sqrt(dot(r, r, count));
	}
	stats.iterations = it;
	stats.relResidual = bNorm > 0.0 ? static_cast<float>(rNorm / bNorm) : 0.0f;
}

} // namespace ihf
