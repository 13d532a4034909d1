// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/warm_up_note.h"

#include <cstdio>

namespace ihf::app {

std::string warmUpNote(int objId, const Expected<WarmUpCost> &cost, float frameBudgetMs)
{
	char line[320];
	if (!cost) {
		std::snprintf(line, sizeof(line), "warm-up of object %d: %s (its first box may overrun)", objId,
			      std::string(cost.error().message.view()).c_str());
		return line;
	}
	if (!(frameBudgetMs > 0) || !(cost->registrationMs > frameBudgetMs))
		return {};
	std::snprintf(line, sizeof(line),
		      "warm-up of object %d: its initial registration took %.1f ms on the largest box%s, more than "
		      "the %g ms frame budget; boxes that large will overrun (the registration is never cut short)",
		      objId, cost->registrationMs, cost->tight ? " (the tight profile)" : "",
		      static_cast<double>(frameBudgetMs));
	return line;
}

} // namespace ihf::app
