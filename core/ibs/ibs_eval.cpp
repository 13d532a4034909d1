// SPDX-License-Identifier: MIT

#include "core/ibs/ibs_eval.h"

#include <algorithm>

namespace ihf {

float evaluateIbs(std::span<const ControlPoint> sortedCps, const Lattice &lattice,
		  const Eigen::Vector3f &x, Eigen::Vector3f *gradient)
{
	int cell[3];
	float u[3], b[3][4], d[3][4];
	for (int a = 0; a < 3; ++a) {
		lattice.locate(x[a], cell[a], u[a]);
		cubicBlend(u[a], b[a]);
		cubicBlendDerivative(u[a], d[a]);
	}
	float f = 0.0f;
	Eigen::Vector3f g = Eigen::Vector3f::Zero();
	const auto less = [](const ControlPoint &cp, int32_t index) { return cp.index < index; };
	for (int l = 0; l < 4; ++l)
		for (int m = 0; m < 4; ++m) {
			const int32_t base = lattice.linear(cell[0] + l, cell[1] + m, cell[2]);
			auto it = std::lower_bound(sortedCps.begin(), sortedCps.end(), base, less);
			for (; it != sortedCps.end() && it->index <= base + 3; ++it) {
				const int p = it->index - base;
				const float w = it->weight;
				f += w * b[0][l] * b[1][m] * b[2][p];
				g.x() += w * d[0][l] * b[1][m] * b[2][p];
				g.y() += w * b[0][l] * d[1][m] * b[2][p];
				g.z() += w * b[0][l] * b[1][m] * d[2][p];
			}
		}
	if (gradient)
		*gradient = g * static_cast<float>(lattice.cells());
	return f;
}

} // namespace ihf
