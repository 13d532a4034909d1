// SPDX-License-Identifier: MIT
#pragma once

// The view-template search as a proposal source (view_search.h): every
// rotation of the model's view templates verified at the best distinct
// voted translations, and at centres taken from the box and the depth alone
// (on the box's ray at each dense slab's median depth); the best proposals
// of each search are scored in full and kept with the voted hypotheses, to
// be polished with them. Not in the paper.

#include "core/estimation/proposal_source.h"

namespace ihf {

// The view search's settings with the score's weights: its sparse score
// ranks by the same rule as the full one.
ViewSearchConfig viewScoring(const EstimatorConfig &config);
// Proposals a view search returns (ViewSearchConfig::keep).
size_t viewKeep(const EstimatorConfig &config);
// Voted translations a box searches (ViewSearchConfig::centres).
int votedCentres(const EstimatorConfig &config);

// One view search at `centre` (anchored in depth when anchor > 0; with
// bySize each rotation placed by the box's size instead, the anchor only
// seeding it: ViewSearchConfig::placeBySize): its proposals scored in full
// and reported under `stage`, into out (at most out.size()); returns how
// many.
size_t searchScored(ProposalBox &box, const Eigen::Vector3d &centre, float anchor, const char *stage,
		    std::span<Hypothesis> out, bool bySize = false);

class ViewTemplateSource : public ProposalSource
{
public:
	bool enabled(const ProposalBox &box) const override;
	// Keeps its proposals in the box's pool; returns the best.
	Hypothesis propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished) override;

private:
	// The depth centres (mm along the box's ray), into out; returns how many.
	static size_t depthAnchors(ProposalBox &box, std::span<float> out);
};

} // namespace ihf
