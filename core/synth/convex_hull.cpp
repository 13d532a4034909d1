// SPDX-License-Identifier: MIT
#include "core/synth/convex_hull.h"

#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace ihf {

Expected<std::vector<HullFacet>> convexHull(const std::vector<Eigen::Vector3d> &points,
					    double mergeDistance)
{
	if (points.size() < 4)
		return makeError(Errc::kInvalidArgument, "convex hull: fewer than 4 points");
	std::vector<coordT> coords;
	coords.reserve(points.size() * 3);
	for (const auto &p : points) {
		coords.push_back(p.x());
		coords.push_back(p.y());
		coords.push_back(p.z());
	}
	// Qhull reports problems on a FILE: collect them for the error message.
	char *errText = nullptr;
	size_t errSize = 0;
	FILE *err = open_memstream(&errText, &errSize);
	qhT qhData;
	qhT *qh = &qhData;
	qh_zero(qh, err);
	char command[64];
	if (mergeDistance > 0)
		std::snprintf(command, sizeof(command), "qhull C-%g", mergeDistance);
	else
		std::snprintf(command, sizeof(command), "qhull");
	const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
				      command, nullptr, err);
	std::vector<HullFacet> facets;
	if (code == 0) {
		facetT *facet;
		vertexT *vertex, **vertexp;
		FORALLfacets {
			HullFacet f;
			f.normal = {facet->normal[0], facet->normal[1], facet->normal[2]};
			f.offset = -facet->offset;
			FOREACHvertex_(facet->vertices)
				f.vertices.push_back({vertex->point[0], vertex->point[1], vertex->point[2]});
			facets.push_back(std::move(f));
		}
	}
	qh_freeqhull(qh, !qh_ALL);
	int curlong, totlong;
	qh_memfreeshort(qh, &curlong, &totlong);
	std::fclose(err);
	std::string message = errText ? errText : "";
	std::free(errText);
	if (code != 0)
		return makeError(Errc::kInvalidArgument,
				 "convex hull: qhull failed (" + std::to_string(code) + "): " +
					 message.substr(0, 300));
	return facets;
}

} // namespace ihf
