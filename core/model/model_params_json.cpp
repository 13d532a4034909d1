// SPDX-License-Identifier: MIT
#include "core/model/model_params_json.h"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace ihf {

namespace {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

template<typename E>
struct EnumName {
	E value;
	const char *name;
};

constexpr std::array<EnumName<HocpWeighting>, 3> kWeightingNames{{
	{HocpWeighting::kCount, "count"},
	{HocpWeighting::kAbsWeight, "abs_weight"},
	{HocpWeighting::kSignSplit, "sign_split"},
}};
constexpr std::array<EnumName<PartKind>, 2> kPartKindNames{{
	{PartKind::kFixed, "fixed"},
	{PartKind::kVariable, "variable"},
}};
constexpr std::array<EnumName<PartCap>, 2> kPartCapNames{{
	{PartCap::kUniform, "uniform"},
	{PartCap::kLargestWeight, "largest_weight"},
}};
constexpr std::array<EnumName<IbsSolver>, 2> kSolverNames{{
	{IbsSolver::kConjugateGradient, "conjugate_gradient"},
	{IbsSolver::kMultilevelBa, "multilevel_ba"},
}};
constexpr std::array<EnumName<IbsWarmStart>, 3> kWarmStartNames{{
	{IbsWarmStart::kZero, "zero"},
	{IbsWarmStart::kMultilevelBa, "multilevel_ba"},
	{IbsWarmStart::kPrevious, "previous"},
}};

template<typename E, size_t N>
const char *enumName(const std::array<EnumName<E>, N> &names, E value)
{
	for (const auto &n : names)
		if (n.value == value)
			return n.name;
	return nullptr;
}

// The shortest decimal that reads back as the same float, as a double, so the
// JSON shows 0.05 rather than 0.05000000074505806. Falls back to the exact
// widening when double rounding would change the float.
double floatForJson(float f)
{
	std::array<char, 64> buf;
	auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), f);
	if (ec != std::errc())
		return f;
	double d = 0;
	auto parsed = std::from_chars(buf.data(), end, d);
	if (parsed.ec != std::errc() || static_cast<float>(d) != f)
		return f;
	return d;
}

// Builds the JSON, remembering the first non-finite field.
class Writer
{
public:
	void put(OrderedJson &obj, const std::string &path, const char *key, float v)
	{
		check(path, key, std::isfinite(v));
		obj[key] = floatForJson(v);
	}
	void put(OrderedJson &obj, const std::string &path, const char *key, double v)
	{
		check(path, key, std::isfinite(v));
		obj[key] = v;
	}
	void putFloats(OrderedJson &obj, const std::string &path, const char *key,
		       const std::vector<float> &values)
	{
		OrderedJson list = OrderedJson::array();
		for (size_t i = 0; i < values.size(); ++i) {
			check(path, std::string(key) + "[" + std::to_string(i) + "]",
			      std::isfinite(values[i]));
			list.push_back(floatForJson(values[i]));
		}
		obj[key] = std::move(list);
	}

	std::optional<std::string> badField;

private:
	void check(const std::string &path, const std::string &key, bool finite)
	{
		if (!finite && !badField)
			badField = path.empty() ? key : path + "." + key;
	}
};

// Collects the first error of a strict read.
class Reader
{
public:
	explicit Reader(std::string_view source) : source_(source) {}

	bool failed() const { return error_.has_value(); }
	const Error &error() const { return *error_; }

	void fail(Errc code, const std::string &path, const std::string &what)
	{
		if (error_)
			return;
		std::string msg(source_);
		msg += ": ";
		if (!path.empty())
			msg += path + ": ";
		error_ = makeError(code, msg + what);
	}

private:
	std::string_view source_;
	std::optional<Error> error_;
};

const char *typeName(const Json &v)
{
	if (v.is_number_integer())
		return "integer";
	if (v.is_number())
		return "number";
	return v.type_name();
}

// One JSON object being read: typed field access plus the unknown-key check.
// A scope over a missing or non-object value is inert (its reads do nothing;
// the error has been recorded already).
class Scope
{
public:
	Scope(Reader &reader, const Json *obj, std::string path)
		: reader_(reader), obj_(obj), path_(std::move(path))
	{
		if (obj_ && !obj_->is_object()) {
			reader_.fail(Errc::kParse, path_,
				     std::string("expected an object, got ") + typeName(*obj_));
			obj_ = nullptr;
		}
	}

	Scope sub(const char *name) { return Scope(reader_, find(name), child(name)); }

	void integer(const char *name, int &out, int min = std::numeric_limits<int>::min())
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_number_integer())
			return typeError(name, "an integer", *v);
		bool fits = v->is_number_unsigned()
				    ? v->get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<int>::max())
				    : v->get<int64_t>() >= std::numeric_limits<int>::min() &&
					      v->get<int64_t>() <= std::numeric_limits<int>::max();
		if (!fits)
			return reader_.fail(Errc::kOutOfRange, child(name), "integer out of range");
		int value = static_cast<int>(v->get<int64_t>());
		if (value < min)
			return reader_.fail(Errc::kOutOfRange, child(name),
					    "must be at least " + std::to_string(min) + ", got " +
						    std::to_string(value));
		out = value;
	}

	void unsigned64(const char *name, uint64_t &out)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_number_unsigned())
			return typeError(name, "a non-negative integer", *v);
		out = v->get<uint64_t>();
	}

	void number(const char *name, double &out)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_number())
			return typeError(name, "a number", *v);
		out = v->get<double>();
	}

	void number(const char *name, float &out)
	{
		double d = 0;
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_number())
			return typeError(name, "a number", *v);
		d = v->get<double>();
		if (!(std::abs(d) <= std::numeric_limits<float>::max()))
			return reader_.fail(Errc::kOutOfRange, child(name), "number outside the float range");
		out = static_cast<float>(d);
	}

	void boolean(const char *name, bool &out)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_boolean())
			return typeError(name, "true or false", *v);
		out = v->get<bool>();
	}

	void string(const char *name, std::string &out)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_string())
			return typeError(name, "a string", *v);
		out = v->get<std::string>();
	}

	void floats(const char *name, std::vector<float> &out)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_array())
			return typeError(name, "a list of numbers", *v);
		std::vector<float> values;
		for (size_t i = 0; i < v->size(); ++i) {
			const Json &e = (*v)[i];
			std::string at = child(name) + "[" + std::to_string(i) + "]";
			if (!e.is_number())
				return reader_.fail(Errc::kParse, at,
						    std::string("expected a number, got ") + typeName(e));
			double d = e.get<double>();
			if (!(std::abs(d) <= std::numeric_limits<float>::max()))
				return reader_.fail(Errc::kOutOfRange, at, "number outside the float range");
			values.push_back(static_cast<float>(d));
		}
		out = std::move(values);
	}

	template<typename E, size_t N>
	void enumeration(const char *name, E &out, const std::array<EnumName<E>, N> &names)
	{
		const Json *v = find(name);
		if (!v)
			return;
		if (!v->is_string())
			return typeError(name, "a string", *v);
		const std::string s = v->get<std::string>();
		std::string expected;
		for (const auto &n : names) {
			if (s == n.name) {
				out = n.value;
				return;
			}
			expected += expected.empty() ? "" : ", ";
			expected += n.name;
		}
		reader_.fail(Errc::kParse, child(name),
			     "unknown value \"" + s + "\" (expected one of " + expected + ")");
	}

	// Call after all fields were read: any key not asked for is an error.
	void rejectUnknownKeys()
	{
		if (!obj_)
			return;
		for (const auto &item : obj_->items()) {
			bool known = false;
			for (const auto &k : seen_)
				known = known || k == item.key();
			if (!known)
				return reader_.fail(Errc::kParse, child(item.key().c_str()),
						    "unknown field");
		}
	}

private:
	std::string child(const char *name) const
	{
		return path_.empty() ? std::string(name) : path_ + "." + name;
	}

	const Json *find(const char *name)
	{
		if (!obj_)
			return nullptr;
		seen_.push_back(name);
		auto it = obj_->find(name);
		if (it == obj_->end()) {
			reader_.fail(Errc::kParse, child(name), "missing field");
			return nullptr;
		}
		return &*it;
	}

	void typeError(const char *name, const char *expected, const Json &v)
	{
		reader_.fail(Errc::kParse, child(name),
			     std::string("expected ") + expected + ", got " + typeName(v));
	}

	Reader &reader_;
	const Json *obj_;
	std::string path_;
	std::vector<std::string> seen_;
};

} // namespace

Expected<std::string> modelParamsToJson(const ModelParams &p)
{
	Writer w;
	OrderedJson j;
	j["obj_id"] = p.objId;
	w.put(j, "", "diameter", p.diameter);
	j["symmetric"] = p.symmetric;
	j["mesh_name"] = p.meshName;

	OrderedJson cloud;
	cloud["normal_step"] = p.cloud.normalStep;
	w.put(cloud, "cloud", "max_jump_mm", p.cloud.maxJumpMm);
	w.put(cloud, "cloud", "max_jump_rel", p.cloud.maxJumpRel);
	cloud["pixel_stride"] = p.cloud.pixelStride;
	j["cloud"] = std::move(cloud);

	OrderedJson ibs;
	ibs["n"] = p.ibs.n;
	ibs["solver"] = enumName(kSolverNames, p.ibs.solver);
	w.put(ibs, "ibs", "offset_cells", p.ibs.offsetCells);
	w.put(ibs, "ibs", "offset_value", p.ibs.offsetValue);
	ibs["max_points"] = p.ibs.maxPoints;
	ibs["warm_start"] = enumName(kWarmStartNames, p.ibs.warmStart);
	ibs["cg_max_iterations"] = p.ibs.cgMaxIterations;
	w.put(ibs, "ibs", "cg_tolerance", p.ibs.cgTolerance);
	w.put(ibs, "ibs", "smoothness", p.ibs.smoothness);
	w.put(ibs, "ibs", "ridge", p.ibs.ridge);
	ibs["mba_levels"] = p.ibs.mbaLevels;
	j["ibs"] = std::move(ibs);

	OrderedJson parts;
	parts["kind"] = enumName(kPartKindNames, p.parts.kind);
	parts["stride"] = p.parts.stride;
	w.put(parts, "parts", "fixed_fraction", p.parts.fixedFraction);
	w.put(parts, "parts", "variable_side", p.parts.variableSide);
	w.put(parts, "parts", "depth_margin_cells", p.parts.depthMarginCells);
	parts["max_control_points"] = p.parts.maxControlPoints;
	parts["cap"] = enumName(kPartCapNames, p.parts.cap);
	parts["min_data_points"] = p.parts.minDataPoints;
	j["parts"] = std::move(parts);

	OrderedJson hocp;
	hocp["n_r"] = p.hocp.nR;
	hocp["n_theta"] = p.hocp.nTheta;
	hocp["n_phi"] = p.hocp.nPhi;
	w.put(hocp, "hocp", "r_min_fraction", p.hocp.rMinFraction);
	hocp["weighting"] = enumName(kWeightingNames, p.hocp.weighting);
	j["hocp"] = std::move(hocp);

	w.put(j, "", "depth_check_margin_mm", p.depthCheckMarginMm);

	OrderedJson training;
	w.putFloats(training, "training", "scales", p.trainScales);
	training["views"] = p.trainViews;
	training["samples"] = p.trainSamples;
	w.put(training, "training", "seconds", p.trainSeconds);
	training["seed"] = p.seed;
	j["training"] = std::move(training);

	if (w.badField)
		return makeError(Errc::kInvalidArgument,
				 "model parameters: " + *w.badField +
					 ": not a finite number (JSON cannot hold it)");
	// An enum value outside its name table would have become null.
	for (const char *section : {"ibs", "parts", "hocp"})
		for (const auto &item : j[section].items())
			if (item.value().is_null())
				return makeError(Errc::kInvalidArgument,
						 std::string("model parameters: ") + section + "." +
							 item.key() + ": enum value out of range");
	return j.dump(2) + "\n";
}

Expected<ModelParams> modelParamsFromJson(std::string_view text, std::string_view source)
{
	Json j;
	try {
		j = Json::parse(text.begin(), text.end());
	} catch (const Json::parse_error &e) {
		std::string what = e.what();
		if (auto pos = what.find("] "); pos != std::string::npos)
			what = what.substr(pos + 2);
		return makeError(Errc::kParse, std::string(source) + ": malformed JSON (byte " +
						       std::to_string(e.byte) + "): " + what);
	} catch (const Json::exception &e) {
		return makeError(Errc::kParse, std::string(source) + ": malformed JSON: " + e.what());
	}

	ModelParams p;
	Reader reader(source);
	Scope root(reader, &j, "");
	root.integer("obj_id", p.objId);
	root.number("diameter", p.diameter);
	root.boolean("symmetric", p.symmetric);
	root.string("mesh_name", p.meshName);

	Scope cloud = root.sub("cloud");
	cloud.integer("normal_step", p.cloud.normalStep, 1);
	cloud.number("max_jump_mm", p.cloud.maxJumpMm);
	cloud.number("max_jump_rel", p.cloud.maxJumpRel);
	cloud.integer("pixel_stride", p.cloud.pixelStride, 1);
	cloud.rejectUnknownKeys();

	Scope ibs = root.sub("ibs");
	ibs.integer("n", p.ibs.n, 1);
	ibs.enumeration("solver", p.ibs.solver, kSolverNames);
	ibs.number("offset_cells", p.ibs.offsetCells);
	ibs.number("offset_value", p.ibs.offsetValue);
	ibs.integer("max_points", p.ibs.maxPoints, 1);
	ibs.enumeration("warm_start", p.ibs.warmStart, kWarmStartNames);
	ibs.integer("cg_max_iterations", p.ibs.cgMaxIterations, 0);
	ibs.number("cg_tolerance", p.ibs.cgTolerance);
	ibs.number("smoothness", p.ibs.smoothness);
	ibs.number("ridge", p.ibs.ridge);
	ibs.integer("mba_levels", p.ibs.mbaLevels, 1);
	ibs.rejectUnknownKeys();

	Scope parts = root.sub("parts");
	parts.enumeration("kind", p.parts.kind, kPartKindNames);
	parts.integer("stride", p.parts.stride, 1);
	parts.number("fixed_fraction", p.parts.fixedFraction);
	parts.number("variable_side", p.parts.variableSide);
	parts.number("depth_margin_cells", p.parts.depthMarginCells);
	parts.integer("max_control_points", p.parts.maxControlPoints, 1);
	parts.enumeration("cap", p.parts.cap, kPartCapNames);
	parts.integer("min_data_points", p.parts.minDataPoints, 0);
	parts.rejectUnknownKeys();

	// The bin counts fix the descriptor length the forest was built for.
	Scope hocp = root.sub("hocp");
	hocp.integer("n_r", p.hocp.nR, 1);
	hocp.integer("n_theta", p.hocp.nTheta, 1);
	hocp.integer("n_phi", p.hocp.nPhi, 1);
	hocp.number("r_min_fraction", p.hocp.rMinFraction);
	hocp.enumeration("weighting", p.hocp.weighting, kWeightingNames);
	hocp.rejectUnknownKeys();
	if (!reader.failed())
		if (std::string problem = hocpBinsProblem(p.hocp); !problem.empty())
			reader.fail(Errc::kOutOfRange, "hocp", problem);

	root.number("depth_check_margin_mm", p.depthCheckMarginMm);

	Scope training = root.sub("training");
	training.floats("scales", p.trainScales);
	training.integer("views", p.trainViews, 0);
	training.integer("samples", p.trainSamples, 0);
	training.number("seconds", p.trainSeconds);
	training.unsigned64("seed", p.seed);
	training.rejectUnknownKeys();

	root.rejectUnknownKeys();
	if (reader.failed())
		return reader.error();
	return p;
}

} // namespace ihf
