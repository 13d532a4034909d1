// SPDX-License-Identifier: MIT
// Readers and writers of the BOP JSON files (camera.json, models_info.json,
// scene_camera.json, scene_gt.json, scene_gt_info.json, detections). The
// results CSV lives in results_csv.cpp, the PNG codecs in png_io.cpp.

#include "core/dataset/bop_io.h"

#include <cmath>
#include <string>

#include "core/dataset/atomic_file.h"
#include "core/dataset/json_fields.h"

namespace ihf {

using namespace bopjson;

namespace {

Pose poseFromRowMajor(const double r[9], const double t[3])
{
	Pose pose;
	for (int i = 0; i < 3; ++i) {
		for (int j = 0; j < 3; ++j)
			pose.R(i, j) = r[3 * i + j];
		pose.t(i) = t[i];
	}
	return pose;
}

OrderedJson rowMajor(const Eigen::Matrix3d &r)
{
	OrderedJson a = OrderedJson::array();
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			a.push_back(r(i, j));
	return a;
}

OrderedJson vec3(const Eigen::Vector3d &v)
{
	return OrderedJson::array({v.x(), v.y(), v.z()});
}

// Reads the top-level object of a file keyed by ids and calls
// parse(value, path, id) for every entry, in numeric id order.
template<typename Parse>
Status forEachIdEntry(const fs::path &file, Parse parse)
{
	auto json = loadJson(file);
	if (!json)
		return json.error();
	JsonPath root(file);
	if (Status s = expectObject(*json, root); !s)
		return s;
	std::map<int, std::pair<std::string, const Json *>> byId;
	for (const auto &[key, value] : json->items()) {
		auto id = parseIdKey(key, root);
		if (!id)
			return id.error();
		auto [it, inserted] = byId.try_emplace(*id, key, &value);
		if (!inserted)
			return root.key(key).error(Errc::kParse, "duplicate id " + std::to_string(*id) +
								  " (also as \"" + it->second.first + "\")");
	}
	for (const auto &[id, entry] : byId)
		if (Status s = parse(*entry.second, root.key(entry.first), id); !s)
			return s;
	return {};
}

// Reads a file keyed by image id whose values are lists of per-instance
// objects, each parsed by parseOne(value, path, out).
template<typename T, typename ParseOne>
Expected<std::map<int, std::vector<T>>> readIdLists(const fs::path &file, ParseOne parseOne)
{
	std::map<int, std::vector<T>> out;
	Status s = forEachIdEntry(file, [&](const Json &list, const JsonPath &at, int id) -> Status {
		if (Status e = expectArray(list, at); !e)
			return e;
		auto &items = out[id];
		items.reserve(list.size());
		for (size_t i = 0; i < list.size(); ++i) {
			JsonPath itemAt = at.index(i);
			if (Status e = expectObject(list[i], itemAt); !e)
				return e;
			T item;
			if (Status e = parseOne(list[i], itemAt, item); !e)
				return e;
			items.push_back(std::move(item));
		}
		return {};
	});
	if (!s)
		return s.error();
	return out;
}

template<typename T, typename ToJson>
Status writeIdLists(const fs::path &file, const std::map<int, std::vector<T>> &data, ToJson toJson)
{
	JsonPath root(file);
	std::vector<std::pair<std::string, std::vector<std::string>>> entries;
	for (const auto &[id, items] : data) {
		if (id < 0)
			return root.error(Errc::kInvalidArgument, "negative image id " + std::to_string(id));
		std::string key = std::to_string(id);
		std::vector<std::string> lines;
		for (size_t i = 0; i < items.size(); ++i) {
			auto line = compactJson(toJson(items[i]), root.key(key).index(i));
			if (!line)
				return line.error();
			lines.push_back(std::move(*line));
		}
		entries.emplace_back(std::move(key), std::move(lines));
	}
	return writeFileAtomic(file, layoutMapOfLists(entries));
}

Status checkPositive(double v, const JsonPath &at)
{
	if (!(v > 0) || !std::isfinite(v))
		return at.error(Errc::kOutOfRange, "must be a positive number, got " + std::to_string(v));
	return {};
}

} // namespace

/* camera.json */

Expected<BopCamera> readBopCamera(const fs::path &file)
{
	auto json = loadJson(file);
	if (!json)
		return json.error();
	JsonPath at(file);
	if (Status s = expectObject(*json, at); !s)
		return s.error();

	BopCamera cam;
	CameraIntrinsics &k = cam.intrinsics;
	using DoubleField = std::pair<const char *, double *>;
	using IntField = std::pair<const char *, int *>;
	for (auto [name, value] : {DoubleField{"fx", &k.fx}, DoubleField{"fy", &k.fy},
				   DoubleField{"cx", &k.cx}, DoubleField{"cy", &k.cy}})
		if (Status s = readNumber(*json, at, name, *value); !s)
			return s.error();
	for (auto [name, value] : {IntField{"width", &k.width}, IntField{"height", &k.height}}) {
		if (Status s = readInt(*json, at, name, *value); !s)
			return s.error();
		if (*value <= 0)
			return at.field(name).error(Errc::kOutOfRange, "must be positive, got " +
									  std::to_string(*value));
	}
	for (auto [name, value] : {DoubleField{"fx", &k.fx}, DoubleField{"fy", &k.fy}})
		if (Status s = checkPositive(*value, at.field(name)); !s)
			return s.error();
	// Every BOP camera.json has depth_scale; default to 1 (mm) if absent.
	if (json->contains("depth_scale")) {
		if (Status s = readNumber(*json, at, "depth_scale", cam.depthScale); !s)
			return s.error();
		if (Status s = checkPositive(cam.depthScale, at.field("depth_scale")); !s)
			return s.error();
	}
	return cam;
}

Status writeBopCamera(const fs::path &file, const BopCamera &camera)
{
	const CameraIntrinsics &k = camera.intrinsics;
	OrderedJson j;
	j["cx"] = k.cx;
	j["cy"] = k.cy;
	j["depth_scale"] = camera.depthScale;
	j["fx"] = k.fx;
	j["fy"] = k.fy;
	j["height"] = k.height;
	j["width"] = k.width;
	auto text = compactJson(j, JsonPath(file));
	if (!text)
		return text.error();
	return writeFileAtomic(file, *text + "\n");
}

/* models/models_info.json */

Expected<std::map<int, ModelInfo>> readModelsInfo(const fs::path &file)
{
	std::map<int, ModelInfo> out;
	Status s = forEachIdEntry(file, [&](const Json &v, const JsonPath &at, int id) -> Status {
		if (Status e = expectObject(v, at); !e)
			return e;
		ModelInfo info;
		info.objId = id;
		if (Status e = readNumber(v, at, "diameter", info.diameter); !e)
			return e;
		const char *minNames[3] = {"min_x", "min_y", "min_z"};
		const char *sizeNames[3] = {"size_x", "size_y", "size_z"};
		for (int i = 0; i < 3; ++i) {
			if (Status e = readNumber(v, at, minNames[i], info.min(i)); !e)
				return e;
			if (Status e = readNumber(v, at, sizeNames[i], info.size(i)); !e)
				return e;
		}

		if (auto it = v.find("symmetries_discrete"); it != v.end()) {
			JsonPath listAt = at.field("symmetries_discrete");
			if (Status e = expectArray(*it, listAt); !e)
				return e;
			for (size_t i = 0; i < it->size(); ++i) {
				double m[16];
				if (Status e = asNumbers((*it)[i], listAt.index(i), m, 16); !e)
					return e;
				// A rigid 4x4: anything else in the last row is a corrupt file.
				if (std::abs(m[12]) > 1e-6 || std::abs(m[13]) > 1e-6 ||
				    std::abs(m[14]) > 1e-6 || std::abs(m[15] - 1) > 1e-6)
					return listAt.index(i).error(Errc::kParse,
								     "last row of the 4x4 transform is not 0 0 0 1");
				double r[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
				double t[3] = {m[3], m[7], m[11]};
				info.symmetriesDiscrete.push_back(poseFromRowMajor(r, t));
			}
		}

		if (auto it = v.find("symmetries_continuous"); it != v.end()) {
			JsonPath listAt = at.field("symmetries_continuous");
			if (Status e = expectArray(*it, listAt); !e)
				return e;
			info.hasContinuousSymmetry = true;
			for (size_t i = 0; i < it->size(); ++i) {
				JsonPath symAt = listAt.index(i);
				if (Status e = expectObject((*it)[i], symAt); !e)
					return e;
				ContinuousSymmetry sym;
				if (Status e = readNumbers((*it)[i], symAt, "axis", sym.axis.data(), 3); !e)
					return e;
				if (Status e = readNumbers((*it)[i], symAt, "offset", sym.offset.data(), 3); !e)
					return e;
				if (sym.axis.norm() == 0)
					return symAt.field("axis").error(Errc::kParse, "axis is the zero vector");
				info.symmetriesContinuous.push_back(sym);
			}
		}
		out.emplace(id, std::move(info));
		return {};
	});
	if (!s)
		return s.error();
	return out;
}

Status writeModelsInfo(const fs::path &file, const std::map<int, ModelInfo> &info)
{
	JsonPath root(file);
	KeyedEntries entries;
	for (const auto &[id, m] : info) {
		std::string key = std::to_string(id);
		if (id < 0 || (m.objId != 0 && m.objId != id))
			return root.key(key).error(Errc::kInvalidArgument,
						   "map key and objId " + std::to_string(m.objId) +
							   " disagree");
		OrderedJson j;
		j["diameter"] = m.diameter;
		j["min_x"] = m.min.x();
		j["min_y"] = m.min.y();
		j["min_z"] = m.min.z();
		j["size_x"] = m.size.x();
		j["size_y"] = m.size.y();
		j["size_z"] = m.size.z();
		if (m.hasContinuousSymmetry || !m.symmetriesContinuous.empty()) {
			OrderedJson list = OrderedJson::array();
			for (const ContinuousSymmetry &sym : m.symmetriesContinuous) {
				OrderedJson s;
				s["axis"] = vec3(sym.axis);
				s["offset"] = vec3(sym.offset);
				list.push_back(std::move(s));
			}
			j["symmetries_continuous"] = std::move(list);
		}
		if (!m.symmetriesDiscrete.empty()) {
			OrderedJson list = OrderedJson::array();
			for (const Pose &p : m.symmetriesDiscrete) {
				OrderedJson a = OrderedJson::array();
				for (int r = 0; r < 3; ++r) {
					for (int c = 0; c < 3; ++c)
						a.push_back(p.R(r, c));
					a.push_back(p.t(r));
				}
				for (double v : {0.0, 0.0, 0.0, 1.0})
					a.push_back(v);
				list.push_back(std::move(a));
			}
			j["symmetries_discrete"] = std::move(list);
		}
		auto text = compactJson(j, root.key(key));
		if (!text)
			return text.error();
		entries.emplace_back(key, std::move(*text));
	}
	return writeFileAtomic(file, layoutMap(entries));
}

/* scene_camera.json */

Expected<std::map<int, SceneCamera>> readSceneCamera(const fs::path &file)
{
	std::map<int, SceneCamera> out;
	Status s = forEachIdEntry(file, [&](const Json &v, const JsonPath &at, int id) -> Status {
		if (Status e = expectObject(v, at); !e)
			return e;
		SceneCamera cam;
		double k[9];
		if (Status e = readNumbers(v, at, "cam_K", k, 9); !e)
			return e;
		// Only a pinhole without skew is representable.
		if (std::abs(k[1]) > 1e-6 || std::abs(k[3]) > 1e-9 || std::abs(k[6]) > 1e-9 ||
		    std::abs(k[7]) > 1e-9 || std::abs(k[8] - 1) > 1e-9)
			return at.field("cam_K").error(Errc::kUnsupported,
						       "expected [fx 0 cx; 0 fy cy; 0 0 1]");
		cam.intrinsics.fx = k[0];
		cam.intrinsics.cx = k[2];
		cam.intrinsics.fy = k[4];
		cam.intrinsics.cy = k[5];
		if (Status e = checkPositive(k[0], at.field("cam_K").index(0)); !e)
			return e;
		if (Status e = checkPositive(k[4], at.field("cam_K").index(4)); !e)
			return e;
		if (v.contains("depth_scale")) {
			if (Status e = readNumber(v, at, "depth_scale", cam.depthScale); !e)
				return e;
			if (Status e = checkPositive(cam.depthScale, at.field("depth_scale")); !e)
				return e;
		}
		out.emplace(id, cam);
		return {};
	});
	if (!s)
		return s.error();
	return out;
}

Status writeSceneCamera(const fs::path &file, const std::map<int, SceneCamera> &cams)
{
	JsonPath root(file);
	KeyedEntries entries;
	for (const auto &[id, cam] : cams) {
		std::string key = std::to_string(id);
		if (id < 0)
			return root.key(key).error(Errc::kInvalidArgument, "negative image id");
		OrderedJson j;
		j["cam_K"] = rowMajor(cam.intrinsics.matrix());
		j["depth_scale"] = cam.depthScale;
		auto text = compactJson(j, root.key(key));
		if (!text)
			return text.error();
		entries.emplace_back(key, std::move(*text));
	}
	return writeFileAtomic(file, layoutMap(entries));
}

/* scene_gt.json */

Expected<std::map<int, std::vector<GtInstance>>> readSceneGt(const fs::path &file)
{
	return readIdLists<GtInstance>(file, [](const Json &v, const JsonPath &at, GtInstance &gt) -> Status {
		double r[9], t[3];
		if (Status e = readNumbers(v, at, "cam_R_m2c", r, 9); !e)
			return e;
		if (Status e = readNumbers(v, at, "cam_t_m2c", t, 3); !e)
			return e;
		if (Status e = readInt(v, at, "obj_id", gt.objId); !e)
			return e;
		gt.pose = poseFromRowMajor(r, t);
		return {};
	});
}

Status writeSceneGt(const fs::path &file, const std::map<int, std::vector<GtInstance>> &gt)
{
	return writeIdLists(file, gt, [](const GtInstance &g) {
		OrderedJson j;
		j["cam_R_m2c"] = rowMajor(g.pose.R);
		j["cam_t_m2c"] = vec3(g.pose.t);
		j["obj_id"] = g.objId;
		return j;
	});
}

/* scene_gt_info.json */

Expected<std::map<int, std::vector<GtInfo>>> readSceneGtInfo(const fs::path &file)
{
	return readIdLists<GtInfo>(file, [](const Json &v, const JsonPath &at, GtInfo &info) -> Status {
		if (Status e = readInts(v, at, "bbox_obj", info.bboxObj.data(), 4); !e)
			return e;
		if (Status e = readInts(v, at, "bbox_visib", info.bboxVisib.data(), 4); !e)
			return e;
		if (Status e = readInt(v, at, "px_count_all", info.pxCountAll); !e)
			return e;
		// Some files lack px_count_valid; neither estimation nor evaluation
		// uses it.
		info.pxCountValid = -1;
		if (v.contains("px_count_valid"))
			if (Status e = readInt(v, at, "px_count_valid", info.pxCountValid); !e)
				return e;
		if (Status e = readInt(v, at, "px_count_visib", info.pxCountVisib); !e)
			return e;
		return readNumber(v, at, "visib_fract", info.visibFract);
	});
}

Status writeSceneGtInfo(const fs::path &file, const std::map<int, std::vector<GtInfo>> &info)
{
	return writeIdLists(file, info, [](const GtInfo &g) {
		OrderedJson j;
		j["bbox_obj"] = g.bboxObj;
		j["bbox_visib"] = g.bboxVisib;
		j["px_count_all"] = g.pxCountAll;
		if (g.pxCountValid >= 0)
			j["px_count_valid"] = g.pxCountValid;
		j["px_count_visib"] = g.pxCountVisib;
		j["visib_fract"] = g.visibFract;
		return j;
	});
}

/* Detections: a list of {scene_id, image_id, category_id, score, bbox, time}. */

Expected<std::vector<Detection>> readDetections(const fs::path &file)
{
	auto json = loadJson(file);
	if (!json)
		return json.error();
	JsonPath root(file);
	if (Status s = expectArray(*json, root); !s)
		return s.error();

	std::vector<Detection> out;
	out.reserve(json->size());
	for (size_t i = 0; i < json->size(); ++i) {
		const Json &v = (*json)[i];
		JsonPath at = root.index(i);
		if (Status s = expectObject(v, at); !s)
			return s.error();
		Detection d;
		if (Status s = readInt(v, at, "scene_id", d.sceneId); !s)
			return s.error();
		if (Status s = readInt(v, at, "image_id", d.imageId); !s)
			return s.error();
		if (Status s = readInt(v, at, "category_id", d.categoryId); !s)
			return s.error();
		if (Status s = readNumber(v, at, "score", d.score); !s)
			return s.error();
		if (Status s = readNumbers(v, at, "bbox", d.bbox.data(), 4); !s)
			return s.error();
		// Boxes become int pixel boxes: coordinates beyond any image are
		// refused rather than converted.
		for (size_t k = 0; k < 4; ++k)
			if (!(std::abs(d.bbox[k]) <= 1e6))
				return at.field("bbox").index(k).error(Errc::kOutOfRange,
								       "must lie within +-1e6 pixels, got " +
									       std::to_string(d.bbox[k]));
		// COCO-style files without timing are common; keep the default then.
		if (v.contains("time")) {
			if (Status s = readNumber(v, at, "time", d.time); !s)
				return s.error();
		}
		out.push_back(d);
	}
	return out;
}

Status writeDetections(const fs::path &file, const std::vector<Detection> &dets)
{
	JsonPath root(file);
	std::vector<std::string> lines;
	lines.reserve(dets.size());
	for (size_t i = 0; i < dets.size(); ++i) {
		const Detection &d = dets[i];
		OrderedJson j;
		j["scene_id"] = d.sceneId;
		j["image_id"] = d.imageId;
		j["category_id"] = d.categoryId;
		j["score"] = d.score;
		j["bbox"] = d.bbox;
		j["time"] = d.time;
		auto text = compactJson(j, root.index(i));
		if (!text)
			return text.error();
		lines.push_back(std::move(*text));
	}
	return writeFileAtomic(file, layoutList(lines));
}

} // namespace ihf
