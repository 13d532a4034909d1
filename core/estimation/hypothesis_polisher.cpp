// SPDX-License-Identifier: MIT
#include "core/estimation/hypothesis_polisher.h"

#include "core/estimation/icp_polisher.h"

namespace ihf {

namespace {

// A polish as a hypothesis of h's origin (invalid when ICP could not run).
Hypothesis fromPolish(const PolishResult &polished, const Hypothesis &h)
{
	Hypothesis out;
	if (polished.valid) {
		out.pose = polished.pose;
		out.score = polished.score;
		out.origin = h.origin;
		out.iteration = h.iteration;
		out.valid = true;
	}
	return out;
}

} // namespace

void HypothesisPolisher::maskToHypothesis(const HypothesisScore &h)
{
	workspace_.maskToRange(h.depthMin * config_.psi1, h.depthMax * config_.psi2);
}

Hypothesis HypothesisPolisher::polish(const Hypothesis &h, Stage stage, int slot, const IcpConfig &icp)
{
	return workspace_.threads() == 1 ? polishHere(h, stage, icp) : polishOnSlot(h, slot, icp);
}

void HypothesisPolisher::polishAll(std::span<const Hypothesis> in, std::span<Hypothesis> out, Stage stage)
{
	workspace_.workers().run(static_cast<int>(in.size()), [&](int i, int slot) {
		const size_t c = static_cast<size_t>(i);
		out[c] = polish(in[c], stage, slot, config_.icpConfig);
	});
}

int HypothesisPolisher::rounds(size_t polishes) const
{
	const size_t threads = static_cast<size_t>(workspace_.threads());
	return static_cast<int>((polishes + threads - 1) / threads);
}

Hypothesis HypothesisPolisher::polishHere(const Hypothesis &h, Stage stage, const IcpConfig &icp)
{
	// What ran before is the caller's stage, the cloud the cloud's, the
	// rest ICP's; the caller's lap counts the call.
	timer_.resume(stage);
	maskToHypothesis(h.score);
	const int n = voter_.buildCloud(workspace_.working(), scorer_.intrinsics(), scorer_.model().params());
	const WorkSlot slot = workspace_.slot(0);
	const PolishResult polished =
		polishFromCloud(scorer_.window(), scorer_.model(), h.pose, slot.cloud.first(static_cast<size_t>(n)), icp,
				*slot.renderer, slot.render);
	timer_.resume(Stage::kIcp);
	return fromPolish(polished, h);
}

Hypothesis HypothesisPolisher::polishOnSlot(const Hypothesis &h, int slot, const IcpConfig &icp)
{
	const WorkSlot s = workspace_.slot(slot);
	const PolishBuffers buffers{s.mask, s.cloud, s.renderer, s.render};
	const PolishResult polished = polishInWindow(scorer_.window(), scorer_.model(), h.pose,
						     h.score.depthMin * config_.psi1, h.score.depthMax * config_.psi2,
						     icp, buffers);
	return fromPolish(polished, h);
}

} // namespace ihf
