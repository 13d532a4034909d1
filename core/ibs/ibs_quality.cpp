// SPDX-License-Identifier: MIT

#include "core/ibs/ibs_quality.h"

#include <cmath>

namespace ihf {

IbsFitQuality measureFitQuality(const IbsFitter &fitter,
				std::span<const Eigen::Vector3f> points,
				std::span<const Eigen::Vector3f> normals, const IbsConfig &cfg,
				float probeCells)
{
	IbsFitQuality q;
	const float eps = (probeCells > 0.0f ? probeCells : cfg.offsetCells) * fitter.lattice().delta();
	double sum2 = 0.0, dist2 = 0.0;
	int offsets = 0, correct = 0;
	for (size_t i = 0; i < points.size(); ++i) {
		const Eigen::Vector3f &p = points[i];
		if (!Lattice::inDomain(p))
			continue;
		Eigen::Vector3f g;
		const float fp = fitter.evaluate(p, g);
		const float f = fp / cfg.offsetValue;
		sum2 += static_cast<double>(f) * f;
		// First-order distance, capped at two cells (beyond that the point
		// is off the fitted band, or the gradient vanishes).
		const float cap = 2.0f * fitter.lattice().delta();
		const float gn = g.norm();
		const float dist = std::abs(fp) < cap * gn ? std::abs(fp) / gn : cap;
		dist2 += static_cast<double>(dist) * dist;
		++q.points;
		if (i >= normals.size() || normals[i].squaredNorm() < 0.25f)
			continue;
		const Eigen::Vector3f front = p + eps * normals[i];
		const Eigen::Vector3f back = p - eps * normals[i];
		if (Lattice::inDomain(front)) {
			++offsets;
			correct += fitter.evaluate(front) > 0.0f;
		}
		if (Lattice::inDomain(back)) {
			++offsets;
			correct += fitter.evaluate(back) < 0.0f;
		}
	}
	q.rmsAtData = q.points ? static_cast<float>(std::sqrt(sum2 / q.points)) : 0.0f;
	q.rmsDistance = q.points ? static_cast<float>(std::sqrt(dist2 / q.points)) : 0.0f;
	q.signCorrect = offsets ? static_cast<float>(correct) / offsets : 0.0f;
	return q;
}

} // namespace ihf
