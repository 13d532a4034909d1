// SPDX-License-Identifier: MIT
// The model sampler, and every peer built in on a rendered view of the ape
// at a known pose: each must find it within the ADD-0.1d threshold.

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "benchmarks/peers/model_sampler.h"
#include "core/dataset/bop_dataset.h"
#include "core/features/depth_cloud.h"
#include "core/render/depth_renderer.h"
#include "core/synth/primitive_mesh.h"
#include "tests/common/test_paths.h"
#if IHF_PEER_OPENCV
#include "benchmarks/peers/peer_opencv_ppf.h"
#endif
#if IHF_PEER_OPEN3D
#include "benchmarks/peers/peer_open3d.h"
#endif
#if IHF_PEER_PCL
#include "benchmarks/peers/peer_pcl_fpfh.h"
#include "benchmarks/peers/peer_pcl_icp.h"
#endif

namespace ihf::peers {
namespace {

TEST(ModelSampler, PointsOnTheSurfaceWithOutwardNormalsByArea)
{
	// 100 x 50 x 20 box: the two 100 x 50 faces carry 5000 / 8000 of the area.
	Mesh box = makeBox(100, 50, 20);
	auto m = sampleModel(box, 7, 0, 40000, 3);
	ASSERT_TRUE(m) << m.error().message;
	EXPECT_EQ(m->objId, 7);
	EXPECT_NEAR(m->diameter, std::sqrt(100.0 * 100 + 50 * 50 + 20 * 20), 1e-3);
	ASSERT_EQ(m->points.size(), 40000u);
	const Eigen::Vector3f centre(0, 0, 10);
	int topBottom = 0;
	for (size_t i = 0; i < m->points.size(); ++i) {
		const Eigen::Vector3f p = m->points[i] - centre;
		const Eigen::Vector3f &n = m->normals[i];
		EXPECT_NEAR(n.norm(), 1.0f, 1e-4f);
		// On a face: one coordinate at the half size, the normal along it, outwards.
		const Eigen::Vector3f half(50, 25, 10);
		int axis = 0;
		(p.cwiseAbs() - half).maxCoeff(&axis);
		ASSERT_NEAR(std::abs(p[axis]), half[axis], 1e-3f);
		ASSERT_GT(n[axis] * p[axis], 0.99f * std::abs(p[axis])) << "normal not outward at point " << i;
		topBottom += axis == 2;
	}
	EXPECT_NEAR(topBottom / 40000.0, 5000.0 / 8000.0, 0.01);
}

TEST(ModelSampler, MeshWithoutAreaIsAnError)
{
	Mesh flat;
	flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
	flat.faces = {{0, 1, 2}};
	EXPECT_FALSE(sampleModel(flat, 1, 0, 10, 1));
	flat.faces = {{0, 1, 5}};
	EXPECT_FALSE(sampleModel(flat, 1, 0, 10, 1));
}

// The ape rendered at a known pose, cropped by its box, as every peer sees it.
class PeerOnRenderedView : public ::testing::Test
{
protected:
	void SetUp() override
	{
		render(Eigen::AngleAxisd(2.2, Eigen::Vector3d(0.3, -1, 0.4).normalized()).toRotationMatrix());
	}

	void render(const Eigen::Matrix3d &R)
	{
		auto ds = BopDataset::open(test::lmoDir());
		ASSERT_TRUE(ds) << ds.error().message;
		auto mesh = ds->loadModel(1);
		ASSERT_TRUE(mesh) << mesh.error().message;
		mesh_ = std::move(*mesh);
		auto m = sampleModel(mesh_, 1, ds->modelsInfo().at(1).diameter, 20000, 1);
		ASSERT_TRUE(m) << m.error().message;
		model_ = std::move(*m);

		K_ = kinectV1Intrinsics();
		gt_.R = R;
		gt_.t = Eigen::Vector3d(40, -30, 800);
		Image<float> depth(K_.width, K_.height, 0.0f);
		DepthRenderer renderer(mesh_.vertices.size());
		auto st = renderer.render(mesh_, gt_, K_, depth.view());
		ASSERT_TRUE(st) << st.error().message;
		int x0 = K_.width, y0 = K_.height, x1 = 0, y1 = 0;
		for (int y = 0; y < K_.height; ++y)
			for (int x = 0; x < K_.width; ++x)
				if (depth.at(x, y) > 0)
					x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x),
					y1 = std::max(y1, y);
		ASSERT_LT(x0, x1);
		scene_.clear();
		std::vector<CloudPoint> cloud(static_cast<size_t>(K_.width) * K_.height);
		auto n = cloudFromDepth(depth.view(), K_, PixelBox{x0 - 5, y0 - 5, x1 - x0 + 11, y1 - y0 + 11},
					DepthCloudConfig{}, cloud);
		ASSERT_TRUE(n);
		for (int i = 0; i < *n; ++i)
			if (cloud[i].hasNormal())
				scene_.push_back(cloud[i]);
		ASSERT_GT(scene_.size(), 500u);
	}

	// Mean distance of the model's points under both poses, in diameters.
	double addRelative(const Pose &est) const
	{
		double sum = 0;
		for (const auto &p : model_.points)
			sum += (est.apply(p.cast<double>()) - gt_.apply(p.cast<double>())).norm();
		return sum / model_.points.size() / model_.diameter;
	}

	void expectFound(Peer &peer)
	{
		ASSERT_TRUE(peer.prepare(model_));
		PeerEstimate e = peer.estimate(1, scene_);
		ASSERT_TRUE(e.found) << peer.name() << ": " << e.reason;
		EXPECT_LT(addRelative(e.pose), 0.1) << peer.name();
		// An object the peer was not prepared for has no pose.
		EXPECT_FALSE(peer.estimate(2, scene_).found);
	}

	Mesh mesh_;
	PeerModel model_;
	CameraIntrinsics K_;
	Pose gt_;
	std::vector<CloudPoint> scene_;
};

#if IHF_PEER_OPENCV
TEST_F(PeerOnRenderedView, OpenCvPpf)
{
	OpenCvPpfPeer peer{OpenCvPpfParams{}};
	expectFound(peer);
}
#endif

#if IHF_PEER_OPEN3D
TEST_F(PeerOnRenderedView, Open3dFpfh)
{
	Open3dPeer peer{Open3dParams{}};
	expectFound(peer);
}
#endif

#if IHF_PEER_PCL
TEST_F(PeerOnRenderedView, PclFpfh)
{
	PclFpfhPeer peer{PclFpfhParams{}};
	expectFound(peer);
}

TEST_F(PeerOnRenderedView, PclIcpRefinesANearbyStart)
{
	// ICP alone is local: from its box start (rotation identity) it can
	// only find a pose whose rotation is near identity.
	render(Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitY()).toRotationMatrix());
	PclIcpPeer peer{PclIcpPeerParams{}};
	expectFound(peer);
}
#endif

} // namespace
} // namespace ihf::peers
