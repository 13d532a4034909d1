// SPDX-License-Identifier: MIT
#include "core/estimation/estimator_config.h"

#include <algorithm>

namespace ihf {

namespace {

// A setting bounded by its budget value: the smaller where both are set,
// 0 meaning unset on either side.
int underBound(int own, int budget)
{
	if (budget <= 0)
		return own;
	return own > 0 ? std::min(own, budget) : budget;
}

} // namespace

EstimatorConfig underBudget(EstimatorConfig c)
{
	// Bounded apart from the forest's re-votes: the iterations' bound below
	// does not bound the re-search (estimate() caps it by the requested k).
	if (c.budgetResearchRounds >= 0)
		c.researchRounds = std::min(c.researchRounds, c.budgetResearchRounds);
	if (c.budgetIterations >= 0)
		c.iterations = std::min(c.iterations, c.budgetIterations);
	if (c.budgetDepthWindows >= 0)
		c.depthWindows = std::min(c.depthWindows, c.budgetDepthWindows);
	c.targetParts = underBound(c.targetParts, c.budgetTargetParts);
	c.ibsMaxPoints = underBound(c.ibsMaxPoints, c.budgetIbsMaxPoints);
	c.ibsCgIterations = underBound(c.ibsCgIterations, c.budgetIbsCgIterations);
	c.windowPixels = underBound(c.windowPixels, c.budgetWindowPixels);
	c.views = underBudget(c.views);
	return c;
}

EstimatorConfig underTightBudget(EstimatorConfig c)
{
	c.targetParts = underBound(c.targetParts, c.tightTargetParts);
	c.maxShiftVotes = underBound(c.maxShiftVotes, c.tightMaxShiftVotes);
	c.ibsMaxPoints = underBound(c.ibsMaxPoints, c.tightIbsMaxPoints);
	c.ibsCgIterations = underBound(c.ibsCgIterations, c.tightIbsCgIterations);
	c.maxHypotheses = underBound(c.maxHypotheses, c.tightMaxHypotheses);
	c.rotationModes = underBound(c.rotationModes, c.tightRotationModes);
	c.views.centreShiftShare = std::min(c.views.centreShiftShare, c.tightCentreShiftShare);
	return c;
}

EstimatorConfig underShortBudget(EstimatorConfig c)
{
	c.icpConfig.iterations = underBound(c.icpConfig.iterations, c.shortIcpIterations);
	c.icpConfig.renderOnce = c.icpConfig.renderOnce || c.shortIcpRenderOnce;
	if (c.shortOccludedWeight >= 0)
		c.score.occludedWeight = c.shortOccludedWeight;
	return c;
}

void iterationsAsRegistration(EstimatorConfig &c)
{
	c.iterationIbsMaxPoints = c.iterationIbsCgIterations = 0;
	c.iterationMaxShiftVotes = c.iterationTargetParts = 0;
}

EstimatorConfig forIterations(EstimatorConfig c)
{
	c.ibsMaxPoints = underBound(c.ibsMaxPoints, c.iterationIbsMaxPoints);
	c.ibsCgIterations = underBound(c.ibsCgIterations, c.iterationIbsCgIterations);
	c.maxShiftVotes = underBound(c.maxShiftVotes, c.iterationMaxShiftVotes);
	c.targetParts = underBound(c.targetParts, c.iterationTargetParts);
	return c;
}

ShareSettings underShare(const EstimatorConfig &c, double shareMs)
{
	ShareSettings s{underBudget(c)};
	s.tight = tightShare(c, shareMs);
	if (s.tight)
		s.config = underTightBudget(s.config);
	s.shortRounds = shortShare(c, shareMs);
	if (s.shortRounds)
		s.config = underShortBudget(s.config);
	return s;
}

} // namespace ihf
