// SPDX-License-Identifier: MIT
#include "core/pose/vote_modes.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/geometry/rotation.h"

namespace ihf {

namespace {

Eigen::Quaternionf principalQuaternion(const Eigen::Matrix4f &m)
{
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix4f> es(m);
	Eigen::Vector4f v = es.eigenvectors().col(3); // largest eigenvalue last
	Eigen::Quaternionf q;
	q.coeffs() = v;
	q.normalize();
	return q;
}

// Gaussian-weighted mean of the centres around x; returns the kernel mass.
float meanShiftStep(std::span<const CastVote> votes, const Eigen::Vector3f &x, float inv2s2,
		    float cutoff2, Eigen::Vector3f &out)
{
	Eigen::Vector3f acc = Eigen::Vector3f::Zero();
	float mass = 0;
	for (const auto &v : votes) {
		if (v.weight <= 0)
			continue;
		float d2 = (v.centre - x).squaredNorm();
		if (d2 > cutoff2)
			continue;
		float k = v.weight * std::exp(-d2 * inv2s2);
		acc += k * v.centre;
		mass += k;
	}
	if (mass > 0)
		out = acc / mass;
	else
		out = x;
	return mass;
}

} // namespace

Eigen::Quaternionf averageQuaternion(std::span<const Eigen::Quaternionf> qs,
				    std::span<const float> weights)
{
	Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
	for (size_t i = 0; i < qs.size(); ++i) {
		float w = weights.empty() ? 1.0f : weights[i];
		m.noalias() += w * qs[i].coeffs() * qs[i].coeffs().transpose();
	}
	return principalQuaternion(m);
}

size_t findPoseModes(std::span<const CastVote> votes, const VoteModeConfig &config,
		     VoteModeWorkspace ws, std::span<PoseMode> modes)
{
	if (votes.empty() || modes.empty())
		return 0;
	const float h = config.translationBandwidth;
	const float inv2s2 = 1.0f / (2.0f * h * h);
	const float cutoff = 3.0f * h;
	const float cutoff2 = cutoff * cutoff;
	const float support2 = config.supportRadius * h * config.supportRadius * h;

	// Seeds: positive-weight votes at an even stride over the list.
	size_t positive = 0;
	for (const auto &v : votes)
		positive += v.weight > 0;
	if (positive == 0)
		return 0;
	const size_t seedCount = std::min({positive, ws.seeds.size(),
					   static_cast<size_t>(std::max(1, config.maxSeeds))});
	const size_t stride = std::max<size_t>(1, positive / seedCount);
	size_t s = 0, k = 0;
	for (const auto &v : votes) {
		if (v.weight <= 0)
			continue;
		if (k++ % stride == 0 && s < seedCount)
			ws.seeds[s++] = v.centre;
	}

	// Mean-shift each seed to its mode; merge modes that meet.
	size_t found = 0;
	const float merge2 = config.mergeDistance * h * config.mergeDistance * h;
	for (size_t i = 0; i < s; ++i) {
		Eigen::Vector3f x = ws.seeds[i], next;
		float mass = 0;
		for (int it = 0; it < config.maxIterations; ++it) {
			mass = meanShiftStep(votes, x, inv2s2, cutoff2, next);
			bool done = (next - x).squaredNorm() < 1e-4f * h * h;
			x = next;
			if (done)
				break;
		}
		mass = meanShiftStep(votes, x, inv2s2, cutoff2, next);
		bool merged = false;
		for (size_t m = 0; m < found; ++m) {
			if ((modes[m].centre - x).squaredNorm() < merge2) {
				if (mass > modes[m].translationDensity) {
					modes[m].centre = x;
					modes[m].translationDensity = mass;
				}
				merged = true;
				break;
			}
		}
		if (merged)
			continue;
		if (found < modes.size()) {
			modes[found++] = PoseMode{x, Eigen::Quaternionf::Identity(), mass, 0, 0};
		} else {
			// Replace the weakest mode if this one is stronger.
			auto weakest = std::min_element(modes.begin(), modes.begin() + found,
							[](const PoseMode &a, const PoseMode &b) {
								return a.translationDensity < b.translationDensity;
							});
			if (mass > weakest->translationDensity)
				*weakest = PoseMode{x, Eigen::Quaternionf::Identity(), mass, 0, 0};
		}
	}
	std::sort(modes.begin(), modes.begin() + found, [](const PoseMode &a, const PoseMode &b) {
		return a.translationDensity > b.translationDensity;
	});

	// Rotation mode among each translation mode's supporting votes.
	const float rs = config.rotationBandwidth;
	const float invR = 1.0f / (2.0f * rs * rs);
	std::span<float> w = ws.scratch.first(votes.size());
	for (size_t m = 0; m < found; ++m) {
		PoseMode &mode = modes[m];
		float support = 0;
		for (size_t i = 0; i < votes.size(); ++i) {
			float d2 = (votes[i].centre - mode.centre).squaredNorm();
			w[i] = (votes[i].weight > 0 && d2 <= support2)
				       ? votes[i].weight * std::exp(-d2 * inv2s2)
				       : 0.0f;
			support += votes[i].weight > 0 && d2 <= support2 ? votes[i].weight : 0.0f;
		}
		mode.supportWeight = support;
		if (support <= 0)
			continue;

		// Seeds: the few heaviest supporting votes.
		constexpr int kRotSeeds = 6;
		size_t seedIdx[kRotSeeds];
		int nSeeds = 0;
		for (size_t i = 0; i < votes.size(); ++i) {
			if (w[i] <= 0)
				continue;
			if (nSeeds < kRotSeeds) {
				seedIdx[nSeeds++] = i;
			} else {
				int weakest = 0;
				for (int j = 1; j < kRotSeeds; ++j)
					if (w[seedIdx[j]] < w[seedIdx[weakest]])
						weakest = j;
				if (w[i] > w[seedIdx[weakest]])
					seedIdx[weakest] = i;
			}
		}
		float bestDensity = -1;
		Eigen::Quaternionf bestQ = Eigen::Quaternionf::Identity();
		for (int sIdx = 0; sIdx < nSeeds; ++sIdx) {
			Eigen::Quaternionf q = votes[seedIdx[sIdx]].rotation;
			float density = 0;
			for (int it = 0; it < config.maxIterations; ++it) {
				Eigen::Matrix4f acc = Eigen::Matrix4f::Zero();
				density = 0;
				for (size_t i = 0; i < votes.size(); ++i) {
					if (w[i] <= 0)
						continue;
					float a = quatAngle(q, votes[i].rotation);
					float kk = w[i] * std::exp(-a * a * invR);
					density += kk;
					acc.noalias() += kk * votes[i].rotation.coeffs() *
							 votes[i].rotation.coeffs().transpose();
				}
				Eigen::Quaternionf nq = principalQuaternion(acc);
				bool done = quatAngle(nq, q) < 1e-3f;
				q = nq;
				if (done)
					break;
			}
			if (density > bestDensity) {
				bestDensity = density;
				bestQ = q;
			}
		}
		mode.rotation = bestQ;
		mode.rotationDensity = bestDensity;
	}
	return found;
}

} // namespace ihf
