// SPDX-License-Identifier: MIT
#include "core/estimation/icp_refiner.h"

#include <cmath>

#include <Eigen/Dense>

namespace ihf {

IcpResult refineIcp(std::span<const CloudPoint> cloud, const Mesh &mesh, const Pose &start,
		    const CameraIntrinsics &K, DepthRenderer &renderer, ImageView<float> render,
		    const IcpConfig &config)
{
	IcpResult result;
	result.pose = start;
	for (int it = 0; it < config.iterations; ++it) {
		const float t = config.iterations > 1 ? static_cast<float>(it) / (config.iterations - 1) : 1.0f;
		const float gate = config.maxDistanceMm + t * (config.minDistanceMm - config.maxDistanceMm);
		if (it == 0 || !config.renderOnce) {
			render.fill(0.0f);
			if (!renderer.render(mesh, result.pose, K, render))
				break;
		}
		// The pose change since the render: an observed point is looked
		// up where it sat in the render's frame, and the surface point
		// found there moved back (none when rendered now).
		const bool moved = config.renderOnce && it > 0;
		const Eigen::Matrix3d moveR = result.pose.R * start.R.transpose();
		const Eigen::Vector3d moveT = result.pose.t - moveR * start.t;

		const Eigen::Vector3d c = result.pose.t;
		Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
		Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
		int n = 0;
		double sse = 0;
		for (const auto &pt : cloud) {
			if (!pt.hasNormal())
				continue;
			Eigen::Vector3d p = pt.p.cast<double>();
			int u = pt.u, v = pt.v;
			if (moved) {
				const Eigen::Vector3d p0 = moveR.transpose() * (p - moveT);
				if (!(p0.z() > 0))
					continue;
				const Eigen::Vector2d uv = K.project(p0);
				u = static_cast<int>(std::lround(uv.x()));
				v = static_cast<int>(std::lround(uv.y()));
			}
			if (!render.contains(u, v))
				continue;
			const float rz = render.at(u, v);
			if (!(rz > 0))
				continue;
			Eigen::Vector3d q = K.backProject(u, v, rz);
			if (moved)
				q = moveR * q + moveT;
			if ((q - p).norm() > gate)
				continue;
			Eigen::Vector3d nn = pt.n.cast<double>();
			double r = (q - p).dot(nn);
			Eigen::Matrix<double, 6, 1> J;
			J << (q - c).cross(nn), nn;
			A.noalias() += J * J.transpose();
			b.noalias() -= J * r;
			sse += r * r;
			++n;
		}
		result.correspondences = n;
		if (n < config.minCorrespondences)
			break;
		result.rmsMm = static_cast<float>(std::sqrt(sse / n));
		A.diagonal().array() += 1e-6 * A.diagonal().maxCoeff() + 1e-9;
		Eigen::Matrix<double, 6, 1> x = A.ldlt().solve(b);
		Eigen::Vector3d w = x.head<3>();
		double angle = w.norm();
		Eigen::Matrix3d dR = angle > 1e-12
			? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
			: Eigen::Matrix3d::Identity();
		result.pose.R = dR * result.pose.R;
		result.pose.t = c + x.tail<3>();
		result.iterations = it + 1;
		if (angle < 1e-4 && x.tail<3>().norm() < 0.05)
			break;
	}
	return result;
}

} // namespace ihf
