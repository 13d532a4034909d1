// SPDX-License-Identifier: MIT
#include "firmware_app/commands/estimate_trace.h"

#include <algorithm>
#include <cmath>

namespace ihf::app {

EstimateTrace::EstimateTrace(std::FILE *f, PoseEstimator &estimator, const EstimatorConfig &config)
	: f_(f), estimator_(estimator), config_(config)
{
}

void EstimateTrace::setImage(int sceneId, const BopScene &scene, const std::string &noTruth)
{
	sceneId_ = sceneId;
	scene_ = &scene;
	sceneNoTruth_ = noTruth;
}

void EstimateTrace::begin(uint64_t frame, int objId, const PixelBox &box, ImageView<const float> depthMm,
			  const CameraIntrinsics &K, const ObjectModel &model)
{
	image_ = static_cast<int>(frame);
	obj_ = objId;
	diameter_ = model.params().diameter;
	truth_.clear();
	const auto gtIt = scene_->gt.find(image_);
	const bool known = gtIt != scene_->gt.end() &&
			   std::any_of(gtIt->second.begin(), gtIt->second.end(),
				       [&](const GtInstance &g) { return g.objId == objId; });
	if (!sceneNoTruth_.empty())
		noTruth(sceneNoTruth_);
	else if (!known)
		noTruth("scene_gt.json has no object " + std::to_string(objId) + " in image " + std::to_string(image_));
	if (!known)
		return;
	for (const GtInstance &g : gtIt->second) {
		if (g.objId != objId)
			continue;
		truth_.push_back(g.pose);
		auto gs = estimator_.scorePose(depthMm, K, box, model, config_, g.pose);
		if (gs) {
			HypothesisEvent ev;
			ev.stage = "given";
			ev.pose = g.pose;
			ev.score = *gs;
			onHypothesis(ev);
		}
	}
}

void EstimateTrace::end(ImageView<const float>, const CameraIntrinsics &, const ObjectModel &, const PoseEstimate &e)
{
	std::fprintf(f_,
		     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"stage\":\"result\",\"found\":%s,"
		     "\"reason\":\"%s\",",
		     sceneId_, image_, obj_, e.found ? "true" : "false", e.reason);
	writePose(e.pose);
	std::fprintf(f_, ",\"score\":%.4f,\"confidence\":%.4f,\"margin\":%.4f,\"iterations\":%d,\"best_iteration\":%d,"
		     "\"ambiguous\":%s}\n",
		     e.score.score, e.confidence, e.margin, e.iterationsDone, e.bestIteration,
		     e.ambiguous ? "true" : "false");
}

void EstimateTrace::noTruth(const std::string &why)
{
	std::fprintf(f_, "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"stage\":\"no_truth\",\"reason\":",
		     sceneId_, image_, obj_);
	writeString(why);
	std::fprintf(f_, "}\n");
}

void EstimateTrace::onVotes(const VoteEvent &e)
{
	for (size_t g = 0; g < truth_.size(); ++g) {
		const Eigen::Matrix3f Rg = (e.cropRotation.transpose() * truth_[g].R).cast<float>();
		const Eigen::Vector3f tg = (e.cropRotation.transpose() * truth_[g].t).cast<float>();
		const Eigen::Quaternionf qg(Rg);
		const float cosHalf = std::cos(0.5f * 20.0f * static_cast<float>(M_PI) / 180.0f);
		const float near = static_cast<float>(0.1 * diameter_);
		double all = 0, rot = 0, trans = 0, both = 0;
		for (const CastVote &v : e.votes) {
			const bool r = std::abs(v.rotation.dot(qg)) > cosHalf;
			const bool t = (v.centre - tg).norm() < near;
			all += v.weight;
			rot += r ? v.weight : 0;
			trans += t ? v.weight : 0;
			both += r && t ? v.weight : 0;
		}
		std::fprintf(f_,
			     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"iteration\":%d,\"stage\":\"votes\","
			     "\"pass\":%d,\"truth\":%zu,\"votes\":%zu,\"rot\":%.4f,\"trans\":%.4f,\"both\":%.4f}\n",
			     sceneId_, image_, obj_, e.iteration, e.pass, g, e.votes.size(),
			     all > 0 ? rot / all : 0, all > 0 ? trans / all : 0, all > 0 ? both / all : 0);
	}
}

void EstimateTrace::onHypothesis(const HypothesisEvent &e)
{
	std::fprintf(f_, "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"iteration\":%d,\"stage\":\"%s\",\"rank\":%d,",
		     sceneId_, image_, obj_, e.iteration, e.stage, e.rank);
	writePose(e.pose);
	std::fprintf(f_,
		     ",\"score\":%.4f,\"depth_score\":%.4f,\"box\":%.4f,\"inliers\":%d,\"outliers\":%d,"
		     "\"occluded\":%d,\"rendered\":%d,\"edge\":%.4f,\"edge_drops\":%d,\"edge_continues\":%d,"
		     "\"density\":%.4f}\n",
		     e.score.score, e.score.depthScore, e.score.boxFactor, e.score.inliers, e.score.outliers,
		     e.score.occluded, e.score.rendered, e.score.edgeFactor, e.score.edgeDrops, e.score.edgeContinues,
		     e.voteDensity);
}

void EstimateTrace::onComparison(const ComparisonEvent &e)
{
	std::fprintf(f_,
		     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"stage\":\"comparison\",\"kind\":\"%s\","
		     "\"round\":%d,\"rank\":%d,",
		     sceneId_, image_, obj_, e.kind, e.round, e.rank);
	writePose(e.rival);
	std::fprintf(f_,
		     ",\"axis\":[%.4f,%.4f,%.4f],\"distinct\":%s,\"reported\":%s,\"polished\":%s,\"differing\":%d,"
		     "\"informative\":%d,\"for_best\":%d,\"for_rival\":%d,\"min_pixels\":%d",
		     e.axis.x(), e.axis.y(), e.axis.z(), e.distinct ? "true" : "false", e.reported ? "true" : "false",
		     e.polished ? "true" : "false", e.evidence.differing, e.evidence.informative, e.evidence.forA,
		     e.evidence.forB, e.minPixels);
	if (e.polished)
		std::fprintf(f_, ",\"score\":%.4f", e.score);
	std::fputs("}\n", f_);
}

void EstimateTrace::writeString(const std::string &text)
{
	std::fputc('"', f_);
	for (unsigned char c : text) {
		if (c == '"' || c == '\\')
			std::fprintf(f_, "\\%c", c);
		else if (c < 0x20)
			std::fprintf(f_, "\\u%04x", c);
		else
			std::fputc(c, f_);
	}
	std::fputc('"', f_);
}

void EstimateTrace::writePose(const Pose &p)
{
	const Eigen::Matrix3d &R = p.R;
	std::fprintf(f_, "\"R\":[%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f],\"t\":[%.3f,%.3f,%.3f]", R(0, 0),
		     R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2), p.t.x(), p.t.y(),
		     p.t.z());
}

} // namespace ihf::app
