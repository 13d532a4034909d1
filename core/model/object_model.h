// SPDX-License-Identifier: MIT
#pragma once

// A trained object: its parameters, the mesh inference renders hypotheses
// with, and the forest. Either built in memory by training or loaded from a
// forest file (see forest_file.h), in which case the forest view points
// into the mapped file.

#include <memory>
#include <span>
#include <vector>

#include "core/forest/forest_view.h"
#include "core/geometry/mesh.h"
#include "core/geometry/rotation.h"
#include "core/model/model_params.h"
#include "core/model/near_symmetry.h"
#include "core/pose/view_templates.h"

namespace ihf {

class ObjectModel
{
public:
	virtual ~ObjectModel() = default;
	virtual const ModelParams &params() const = 0;
	virtual const Mesh &mesh() const = 0;
	virtual const ForestView &forest() const = 0;
	// The turns that map most of the object onto itself (near_symmetry.h):
	// from the forest file, or set by training; none otherwise.
	virtual std::span<const NearSymmetry> nearSymmetries() const { return {}; }

	// Sparse view templates for the rotation search (view_search.h): from
	// the forest file, or attached after loading one written without them;
	// empty otherwise.
	const ViewTemplates &viewTemplates() const { return views_; }

	// The mesh hypotheses are rendered with: a simplified copy when one was
	// attached at load (mesh_simplify.h), else the mesh itself.
	const Mesh &renderMesh() const { return renderMesh_.faces.empty() ? mesh() : renderMesh_; }
	void attachRenderMesh(Mesh m)
	{
		renderMesh_ = std::move(m);
		renderClosed_ = orientClosedOutward(renderMesh_);
	}
	// Whether the attached render mesh is closed and (after turning any
	// faces wound the wrong way) wound outwards, so that its back faces can
	// be skipped; the mesh itself is not checked (false).
	bool renderMeshClosed() const { return renderClosed_; }
	void attachViewTemplates(int viewpoints, int pointsPerView, std::vector<Eigen::Vector3f> points)
	{
		ownedViews_ = std::move(points);
		setViewTemplates(ViewTemplates{viewpoints, pointsPerView, ownedViews_});
	}

protected:
	// Templates that live elsewhere (the mapped file); their viewpoints'
	// directions are tabled here, at load.
	void setViewTemplates(const ViewTemplates &views)
	{
		views_ = views;
		viewDirections_.clear();
		for (int v = 0; v < views.viewpoints; ++v)
			viewDirections_.push_back(fibonacciDirection(v, views.viewpoints).cast<float>());
		views_.directions = viewDirections_;
	}

private:
	std::vector<Eigen::Vector3f> ownedViews_;
	std::vector<Eigen::Vector3f> viewDirections_;
	ViewTemplates views_;
	Mesh renderMesh_;
	bool renderClosed_ = false;
};

// An in-memory model holding its own packed forest.
class OwnedObjectModel : public ObjectModel
{
public:
	OwnedObjectModel(ModelParams params, Mesh mesh, ForestStorage storage)
		: params_(std::move(params)), mesh_(std::move(mesh)), storage_(std::move(storage)) {}

	const ModelParams &params() const override { return params_; }
	const Mesh &mesh() const override { return mesh_; }
	const ForestView &forest() const override { return storage_.view(); }
	std::span<const NearSymmetry> nearSymmetries() const override { return nearSymmetries_; }
	const ForestStorage &storage() const { return storage_; }
	void setNearSymmetries(std::vector<NearSymmetry> s) { nearSymmetries_ = std::move(s); }

private:
	std::vector<NearSymmetry> nearSymmetries_;
	ModelParams params_;
	Mesh mesh_;
	ForestStorage storage_;
};

} // namespace ihf
