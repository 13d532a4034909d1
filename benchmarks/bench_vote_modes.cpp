// SPDX-License-Identifier: MIT
// Mode finding on a vote set shaped like an occluded ape box's: 20 000
// votes, a few percent near the true centre and rotation,
// the rest spread over the box's depth slab with confusable rotations.

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/pose/vote_modes.h"

namespace {

using namespace ihf;

std::vector<CastVote> occludedBoxVotes()
{
	std::mt19937_64 rng(7);
	std::normal_distribution<float> n(0, 1);
	std::uniform_real_distribution<float> u(-100, 100);
	const Eigen::Vector3f centre(15, -10, 850);
	const Eigen::Quaternionf truth(Eigen::AngleAxisf(0.8f, Eigen::Vector3f(1, 2, 0).normalized()));
	std::vector<CastVote> votes;
	for (int i = 0; i < 20000; ++i) {
		const bool near = i % 20 < 2;
		Eigen::Vector3f c = near ? Eigen::Vector3f(centre + 4.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)))
					 : Eigen::Vector3f(centre + Eigen::Vector3f(u(rng), u(rng), 0.5f * u(rng)));
		Eigen::Quaternionf q = near && i % 40 == 0
			? truth
			: Eigen::Quaternionf(Eigen::Vector4f(n(rng), n(rng), n(rng), n(rng)).normalized());
		votes.push_back({c, q, 1.0f / 45.0f});
	}
	return votes;
}

void BM_FindPoseModes(benchmark::State &state)
{
	const std::vector<CastVote> votes = occludedBoxVotes();
	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(64);
	std::vector<PoseMode> modes(36);
	VoteModeConfig cfg;
	cfg.translationBandwidth = 0.06f * 102.0f; // the ape's diameter, estimate.toml
	cfg.rotationModesPerCentre = static_cast<int>(state.range(0));
	const size_t slots = std::min<size_t>(modes.size(), 6 * cfg.rotationModesPerCentre);
	for (auto _ : state) {
		size_t found = findPoseModes(votes, cfg, {scratch, seeds, support, packed}, std::span(modes).first(slots));
		benchmark::DoNotOptimize(found);
	}
}
BENCHMARK(BM_FindPoseModes)->Arg(1)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

} // namespace
