// SPDX-License-Identifier: MIT
#pragma once

// How well a fit honours the 3L equations on a point set (normally all the
// points, not just the subsample the fit used).

#include <span>

#include <Eigen/Core>

#include "core/ibs/ibs_config.h"
#include "core/ibs/ibs_fitter.h"

namespace ihf {

struct IbsFitQuality {
	float rmsAtData = 0;   // RMS of f at the points, divided by c
	float rmsDistance = 0; // RMS of |f| / |grad f| at the points: the
			       //   distance to the zero set, unit-cube units
	float signCorrect = 0; // fraction of p +/- probe n with f of the right sign
	int points = 0;        // points inside the unit cube that were scored
};

// probeCells: offset of the sign probes in lattice cells (0: the fit's own
// epsilon, cfg.offsetCells). A fixed probe compares fits with different
// epsilon fairly.
IbsFitQuality measureFitQuality(const IbsFitter &fitter,
				std::span<const Eigen::Vector3f> points,
				std::span<const Eigen::Vector3f> normals, const IbsConfig &cfg,
				float probeCells = 0.0f);

} // namespace ihf
