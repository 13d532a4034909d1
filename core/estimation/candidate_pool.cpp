// SPDX-License-Identifier: MIT
#include "core/estimation/candidate_pool.h"

#include <algorithm>
#include <cmath>

namespace ihf {

bool samePose(const Pose &a, const Pose &b, double sameTranslationMm)
{
	constexpr double kSameRotation = 10.0 * M_PI / 180.0;
	return (a.t - b.t).norm() < sameTranslationMm && rotationAngle(a.R, b.R) < kSameRotation;
}

bool takeBetter(Hypothesis &h, const Hypothesis &candidate)
{
	if (!candidate.valid || (h.valid && !(candidate.score.score > h.score.score)))
		return false;
	h = candidate;
	return true;
}

bool insertByScore(FixedListBase<Hypothesis> &ranked, const Hypothesis &h)
{
	return insertRanked(ranked, h, [](const Hypothesis &x) { return x.score.score; });
}

void CandidatePool::attach(std::span<Hypothesis> kept, std::span<Hypothesis> registrationKept,
			   std::span<RivalPose> rivals)
{
	kept_.setStorage(kept);
	registrationKept_.setStorage(registrationKept);
	rivals_ = RivalPoses(rivals);
}

void CandidatePool::beginBox(const Eigen::Matrix3d &cropRotation, double diameter, int iterations)
{
	kept_.clear();
	registrationKept_.clear();
	rivals_.clear();
	cropRotation_ = cropRotation;
	sameMm_ = static_cast<float>(0.05 * diameter);
	diameter_ = diameter;
	iterations_ = iterations;
}

void CandidatePool::keep(const Hypothesis &h)
{
	keepIn(kept_, h);
	if (h.origin != HypothesisOrigin::kRefinement)
		keepIn(registrationKept_, h);
}

void CandidatePool::keepIn(FixedListBase<Hypothesis> &kept, const Hypothesis &h) const
{
	for (size_t i = 0; i < kept.size(); ++i) {
		if (samePose(kept[i].pose, h.pose, sameMm_)) {
			if (h.score.score <= kept[i].score.score)
				return;
			kept.erase(i); // the better one is inserted below
			break;
		}
	}
	insertByScore(kept, h);
}

int CandidatePool::reportedIteration(const Hypothesis &h) const
{
	switch (h.origin) {
	case HypothesisOrigin::kRegistration:
		return 0;
	case HypothesisOrigin::kRefinement:
		return h.iteration;
	case HypothesisOrigin::kProposal:
		break;
	}
	return iterations_ + 1;
}

void CandidatePool::report(const Hypothesis &h, const char *stage, int rank, float voteDensity)
{
	rivals_.add(h.pose, h.score.score);
	if (!observer_)
		return;
	HypothesisEvent e;
	e.iteration = reportedIteration(h);
	e.stage = stage;
	e.rank = rank;
	e.pose = inRealCamera(h.pose);
	e.score = h.score;
	e.voteDensity = voteDensity;
	observer_->onHypothesis(e);
}

void CandidatePool::reportComparison(ComparisonEvent event) const
{
	if (!observer_)
		return;
	event.rival = inRealCamera(event.rival);
	observer_->onComparison(event);
}

Pose CandidatePool::inRealCamera(const Pose &crop) const
{
	Pose p;
	p.R = cropRotation_ * crop.R;
	p.t = cropRotation_ * crop.t;
	return p;
}

void CandidatePool::reportVotes(int iteration, int pass, std::span<const CastVote> votes) const
{
	if (observer_)
		observer_->onVotes({iteration, pass, cropRotation_, votes});
}

size_t CandidatePool::distinctCentres(double apartMm, std::span<Eigen::Vector3d> out) const
{
	size_t n = 0;
	for (const Hypothesis &h : kept_) {
		if (n == out.size())
			break;
		bool seen = false;
		for (size_t j = 0; j < n; ++j)
			seen = seen || (out[j] - h.pose.t).norm() < apartMm;
		if (!seen)
			out[n++] = h.pose.t;
	}
	return n;
}

// The view proposals outscore an unpolished forest mode that ICP would
// bring to the truth (a mode 11-17 deg off can rank below 16 polished
// proposals once refinement has added its modes to the ranking), so the
// forest's own bests and the registration's are added after a refinement.
void CandidatePool::polishCandidates(const PolishChoice &choice, const Hypothesis &registrationBest,
				     const Hypothesis &refinementBest, FixedListBase<Hypothesis> &out) const
{
	const size_t wanted = static_cast<size_t>(std::max(0, choice.wanted));
	out.clear();
	for (size_t i = 0; i < std::min(kept_.size(), wanted) && !out.full(); ++i)
		static_cast<void>(out.pushBack(kept_[i]));
	if (out.empty() || !refinementBest.valid) // or no refinement ran
		return;
	const double same = 0.05 * diameter_;
	auto add = [&](const Hypothesis &h) {
		bool seen = !h.valid;
		for (size_t i = 0; i < out.size() && !seen; ++i)
			seen = samePose(out[i].pose, h.pose, same);
		if (!seen && !out.full())
			static_cast<void>(out.pushBack(h));
	};
	if (choice.withRegistration)
		for (size_t i = 0; i < std::min(registrationKept_.size(), wanted); ++i)
			add(registrationKept_[i]);
	if (choice.withForestBests) {
		add(registrationBest);
		add(refinementBest);
	}
}

} // namespace ihf
