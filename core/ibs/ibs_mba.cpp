// SPDX-License-Identifier: MIT
// Multilevel B-spline approximation (Lee, Wolberg and Shin 1997) of the 3L
// values. At each level every equation spreads its residual over the 64
// nodes of its support in proportion to the basis weights (BA), and each node
// takes the weighted mean of what it received: one pass, no iteration.
// Coarse levels (half the cells each) use small dense lattices; their spline
// is folded into the fine active control values by sampling it at the fine
// nodes, and the residuals for the next level are taken from the fine
// representation so that the output stays consistent with what is returned.

#include <algorithm>
#include <cmath>

#include "core/ibs/ibs_fitter.h"

namespace ihf {

namespace {

using Vec4 = Eigen::Array4f;

// BA share of one equation with residual r: node weights w = bx by bz,
// num += w^3 r / sum(w^2), den += w^2 (Lee et al. 1997, Eq. 5). columns[16]
// give the first node of each (l, m) column in num/den.
void spreadColumns(const int32_t *columns, const float b[3][4], float r, float *num, float *den)
{
	const Vec4 bx = Eigen::Map<const Vec4>(b[0]);
	const Vec4 by = Eigen::Map<const Vec4>(b[1]);
	const Vec4 bz = Eigen::Map<const Vec4>(b[2]);
	const float sum2 = bx.square().sum() * by.square().sum() * bz.square().sum();
	const float scale = r / sum2;
	const Vec4 bz2 = bz.square();
	const Vec4 bz3 = bz2 * bz;
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m) {
			const float wxy = bx[l] * by[m];
			const float wxy2 = wxy * wxy;
			Eigen::Map<Vec4>(num + columns[l * 4 + m]) += (wxy2 * wxy * scale) * bz3;
			Eigen::Map<Vec4>(den + columns[l * 4 + m]) += wxy2 * bz2;
		}
}

void spread(const Lattice &lattice, const int cell[3], const float b[3][4], float r,
	    float *num, float *den)
{
	int32_t columns[16];
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m)
			columns[l * 4 + m] = lattice.linear(cell[0] + l, cell[1] + m, cell[2]);
	spreadColumns(columns, b, r, num, den);
}

} // namespace

void IbsFitter::solveMba(const IbsConfig &cfg)
{
	const int count = activeCount_;
	const int levels = std::max(cfg.mbaLevels, 1);
	const int cells = lattice_.cells();
	float *x = x_.data();

	for (int ci = 0; ci < constraintCount_; ++ci)
		residual_[ci] = constraints_[ci].value;

	for (int level = 0; level < levels - 1; ++level) {
		const int coarseCells = static_cast<int>(
			std::lround(static_cast<double>(cells) / static_cast<double>(1 << (levels - 1 - level))));
		if (coarseCells < 1 || coarseCells >= cells)
			continue;
		const Lattice coarse(coarseCells + 3);
		const size_t nodes = static_cast<size_t>(coarse.nodeCount());
		if (nodes > coarseNum_.size())
			continue; // cannot happen for cells <= ceil(C / 2)
		float *num = coarseNum_.data(), *den = coarseDen_.data();
		std::fill_n(num, nodes, 0.0f);
		std::fill_n(den, nodes, 0.0f);

		for (int ci = 0; ci < constraintCount_; ++ci) {
			const Constraint &c = constraints_[ci];
			int cell[3];
			float u[3], b[3][4];
			for (int a = 0; a < 3; ++a) {
				coarse.locate(c.pos[a], cell[a], u[a]);
				cubicBlend(u[a], b[a]);
			}
			spread(coarse, cell, b, residual_[ci], num, den);
		}
		for (size_t i = 0; i < nodes; ++i)
			num[i] = den[i] > 0.0f ? num[i] / den[i] : 0.0f;

		// Fold the coarse spline into the fine control values.
		for (int a = 0; a < count; ++a) {
			const Eigen::Vector3f pos = lattice_.nodePosition(active_[a]);
			int cell[3];
			float u[3], b[3][4];
			for (int k = 0; k < 3; ++k) {
				coarse.locate(pos[k], cell[k], u[k]);
				cubicBlend(u[k], b[k]);
			}
			Vec4 acc = Vec4::Zero();
			for (int l = 0; l < 4; ++l)
				for (int m = 0; m < 4; ++m)
					acc += (b[0][l] * b[1][m]) *
					       Eigen::Map<const Vec4>(num + coarse.linear(cell[0] + l, cell[1] + m, cell[2]));
			const float f = (acc * Eigen::Map<const Vec4>(b[2])).sum();
			x[a] += f;
		}
		for (int ci = 0; ci < constraintCount_; ++ci)
			residual_[ci] = constraints_[ci].value - constraintValue(constraints_[ci], x);
	}

	// Finest level on the active set itself.
	float *num = r_.data(), *den = z_.data();
	std::fill_n(num, count, 0.0f);
	std::fill_n(den, count, 0.0f);
	for (int ci = 0; ci < constraintCount_; ++ci) {
		const Constraint &c = constraints_[ci];
		const float b[3][4] = {{c.bx[0], c.bx[1], c.bx[2], c.bx[3]},
				       {c.by[0], c.by[1], c.by[2], c.by[3]},
				       {c.bz[0], c.bz[1], c.bz[2], c.bz[3]}};
		spreadColumns(c.column, b, residual_[ci], num, den);
	}
	for (int a = 0; a < count; ++a)
		if (den[a] > 0.0f)
			x[a] += num[a] / den[a];
}

} // namespace ihf
