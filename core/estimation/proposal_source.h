// SPDX-License-Identifier: MIT
#pragma once

// A proposal source adds hypotheses the votes did not give: the view
// templates searched at the voted and the depth centres, a re-search at the
// polished best, the best hypotheses turned half round. Each is a class
// behind this one small interface (as libcamera's pipeline handlers are
// behind PipelineHandler): the estimator asks whether it runs for the box
// and has it propose; a source asks the budget planner before each of its
// steps, scores, polishes and reports what it finds, and returns its best.

#include <span>

#include <Eigen/Core>

#include "core/estimation/box_scorer.h"
#include "core/estimation/budget_planner.h"
#include "core/estimation/candidate_pool.h"
#include "core/estimation/estimator_config.h"
#include "core/estimation/estimator_workspace.h"
#include "core/estimation/hypothesis_polisher.h"
#include "core/estimation/part_window.h"
#include "core/model/object_model.h"
#include "core/pose/view_search.h"

namespace ihf {

// The box a source proposes in, and the parts of the estimator it uses.
struct ProposalBox {
	const EstimatorConfig &config; // the box's (budgeted) settings
	const ObjectModel &model;
	BoxAxes axes;                  // what the window's box says about the object's place
	Eigen::Vector3d modelCentre;   // the model's box centre
	int requestedIterations = 0;   // k as asked, whatever the budget's bound
	size_t slabs = 0;              // dense depth slabs found in the box
	EstimatorWorkspace &workspace;
	BoxScorer &scorer;
	CandidatePool &pool;
	HypothesisPolisher &polisher;
	BudgetPlanner &planner;
	PartWindow &parts;             // the box as a pose's turns are compared pixel by pixel
};

class ProposalSource
{
public:
	virtual ~ProposalSource() = default;
	// Whether the source runs in this box (its settings, the model).
	virtual bool enabled(const ProposalBox &box) const = 0;
	// Proposes hypotheses; `best` is the best so far, `polished` the polish
	// results. Returns the best hypothesis it found (or `best`, or an
	// invalid one); the estimator takes it when it scores higher.
	virtual Hypothesis propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished) = 0;
};

} // namespace ihf
