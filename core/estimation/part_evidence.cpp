// SPDX-License-Identifier: MIT
#include "core/estimation/part_evidence.h"

#include <cmath>

namespace ihf {

PartEvidence comparePoseRenders(ImageView<const float> observed, ImageView<const float> renderA,
				ImageView<const float> renderB, float toleranceMm)
{
	PartEvidence e;
	for (int y = 0; y < observed.height; ++y)
		for (int x = 0; x < observed.width; ++x) {
			const float a = renderA.at(x, y), b = renderB.at(x, y);
			const bool drawnA = a > 0, drawnB = b > 0;
			if (drawnA == drawnB && (!drawnA || std::abs(a - b) <= toleranceMm))
				continue;
			++e.differing;
			const float o = observed.at(x, y);
			if (!(o > 0))
				continue;
			const bool explainsA = drawnA && std::abs(o - a) <= toleranceMm;
			const bool explainsB = drawnB && std::abs(o - b) <= toleranceMm;
			const bool throughA = drawnA && o > a + toleranceMm;
			const bool throughB = drawnB && o > b + toleranceMm;
			const bool forA = (explainsA && !explainsB) || (throughB && !throughA);
			const bool forB = (explainsB && !explainsA) || (throughA && !throughB);
			if (forA == forB)
				continue;
			++e.informative;
			if (forA)
				++e.forA;
			else
				++e.forB;
		}
	return e;
}

} // namespace ihf
