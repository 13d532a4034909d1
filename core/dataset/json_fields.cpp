// SPDX-License-Identifier: MIT
#include "core/dataset/json_fields.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace ihf::bopjson {

namespace fs = std::filesystem;

JsonPath JsonPath::key(std::string_view key) const
{
	JsonPath p = *this;
	if (!p.path_.empty())
		p.path_ += '.';
	p.path_ += '"';
	p.path_ += key;
	p.path_ += '"';
	return p;
}

JsonPath JsonPath::field(std::string_view name) const
{
	JsonPath p = *this;
	if (!p.path_.empty())
		p.path_ += '.';
	p.path_ += name;
	return p;
}

JsonPath JsonPath::index(size_t i) const
{
	JsonPath p = *this;
	p.path_ += '[' + std::to_string(i) + ']';
	return p;
}

Error JsonPath::error(Errc code, const std::string &what) const
{
	std::string msg = file_->string() + ": ";
	if (!path_.empty())
		msg += path_ + ": ";
	return makeError(code, msg + what);
}

Expected<Json> loadJson(const fs::path &file)
{
	std::error_code ec;
	if (!fs::exists(file, ec))
		return makeError(Errc::kNotFound, file.string() + ": file not found");
	if (fs::is_directory(file, ec))
		return makeError(Errc::kIo, file.string() + ": is a directory, expected a JSON file");

	std::ifstream in(file, std::ios::binary);
	if (!in)
		return makeError(Errc::kIo, file.string() + ": cannot open for reading");
	std::ostringstream text;
	text << in.rdbuf();
	if (in.bad())
		return makeError(Errc::kIo, file.string() + ": read failed");

	try {
		return Json::parse(text.str());
	} catch (const Json::parse_error &e) {
		// what() is "[json.exception.parse_error.101] parse error at line L,
		// column C: ..."; keep the part after the id, add the byte offset.
		std::string what = e.what();
		if (auto pos = what.find("] "); pos != std::string::npos)
			what = what.substr(pos + 2);
		return makeError(Errc::kParse, file.string() + ": malformed JSON (byte " +
					       std::to_string(e.byte) + "): " + what);
	} catch (const Json::exception &e) {
		return makeError(Errc::kParse, file.string() + ": malformed JSON: " + e.what());
	}
}

namespace {

std::string describe(const Json &value)
{
	if (value.is_number_float() || value.is_number_integer())
		return "number " + value.dump();
	return value.type_name();
}

} // namespace

Status expectObject(const Json &value, const JsonPath &at)
{
	if (!value.is_object())
		return at.error(Errc::kParse, "expected an object, got " + describe(value));
	return {};
}

Status expectArray(const Json &value, const JsonPath &at)
{
	if (!value.is_array())
		return at.error(Errc::kParse, "expected a list, got " + describe(value));
	return {};
}

Status asNumber(const Json &value, const JsonPath &at, double &out)
{
	if (!value.is_number())
		return at.error(Errc::kParse, "expected a number, got " + describe(value));
	out = value.get<double>();
	return {};
}

Status asInt(const Json &value, const JsonPath &at, int &out)
{
	constexpr auto lo = std::numeric_limits<int>::min();
	constexpr auto hi = std::numeric_limits<int>::max();
	if (value.is_number_unsigned()) {
		auto v = value.get<uint64_t>();
		if (v > static_cast<uint64_t>(hi))
			return at.error(Errc::kOutOfRange, "integer " + value.dump() + " out of range");
		out = static_cast<int>(v);
		return {};
	}
	if (value.is_number_integer()) {
		auto v = value.get<int64_t>();
		if (v < lo || v > hi)
			return at.error(Errc::kOutOfRange, "integer " + value.dump() + " out of range");
		out = static_cast<int>(v);
		return {};
	}
	// Some tools write ids as 3.0; accept integral floats.
	if (value.is_number_float()) {
		double v = value.get<double>();
		if (std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi) {
			out = static_cast<int>(v);
			return {};
		}
	}
	return at.error(Errc::kParse, "expected an integer, got " + describe(value));
}

Status asNumbers(const Json &value, const JsonPath &at, double *out, size_t count)
{
	if (!value.is_array())
		return at.error(Errc::kParse, "expected a list of " + std::to_string(count) +
					      " numbers, got " + describe(value));
	if (value.size() != count)
		return at.error(Errc::kParse, "expected " + std::to_string(count) +
					      " numbers, got " + std::to_string(value.size()));
	for (size_t i = 0; i < count; ++i)
		if (Status s = asNumber(value[i], at.index(i), out[i]); !s)
			return s;
	return {};
}

Status asInts(const Json &value, const JsonPath &at, int *out, size_t count)
{
	if (!value.is_array())
		return at.error(Errc::kParse, "expected a list of " + std::to_string(count) +
					      " integers, got " + describe(value));
	if (value.size() != count)
		return at.error(Errc::kParse, "expected " + std::to_string(count) +
					      " integers, got " + std::to_string(value.size()));
	for (size_t i = 0; i < count; ++i)
		if (Status s = asInt(value[i], at.index(i), out[i]); !s)
			return s;
	return {};
}

namespace {

Expected<const Json *> findField(const Json &obj, const JsonPath &at, const char *name)
{
	auto it = obj.find(name);
	if (it == obj.end())
		return at.field(name).error(Errc::kParse, "missing field");
	return &*it;
}

} // namespace

Status readNumber(const Json &obj, const JsonPath &at, const char *name, double &out)
{
	auto v = findField(obj, at, name);
	if (!v)
		return v.error();
	return asNumber(**v, at.field(name), out);
}

Status readInt(const Json &obj, const JsonPath &at, const char *name, int &out)
{
	auto v = findField(obj, at, name);
	if (!v)
		return v.error();
	return asInt(**v, at.field(name), out);
}

Status readNumbers(const Json &obj, const JsonPath &at, const char *name, double *out,
		   size_t count)
{
	auto v = findField(obj, at, name);
	if (!v)
		return v.error();
	return asNumbers(**v, at.field(name), out, count);
}

Status readInts(const Json &obj, const JsonPath &at, const char *name, int *out, size_t count)
{
	auto v = findField(obj, at, name);
	if (!v)
		return v.error();
	return asInts(**v, at.field(name), out, count);
}

Expected<int> parseIdKey(const std::string &key, const JsonPath &at)
{
	int id = -1;
	const char *end = key.data() + key.size();
	auto [ptr, ec] = std::from_chars(key.data(), end, id);
	if (key.empty() || ec != std::errc() || ptr != end || id < 0)
		return at.key(key).error(Errc::kParse, "expected a non-negative integer id as key");
	return id;
}

Expected<std::string> compactJson(const OrderedJson &value, const JsonPath &at)
{
	if (value.is_object()) {
		std::string s = "{";
		bool first = true;
		for (const auto &[k, v] : value.items()) {
			auto inner = compactJson(v, at.field(k));
			if (!inner)
				return inner;
			s += first ? "" : ", ";
			s += OrderedJson(k).dump() + ": " + *inner;
			first = false;
		}
		return s + "}";
	}
	if (value.is_array()) {
		std::string s = "[";
		for (size_t i = 0; i < value.size(); ++i) {
			auto inner = compactJson(value[i], at.index(i));
			if (!inner)
				return inner;
			s += (i ? ", " : "") + *inner;
		}
		return s + "]";
	}
	if (value.is_number_float() && !std::isfinite(value.get<double>()))
		return at.error(Errc::kInvalidArgument, "cannot write non-finite number " +
							std::to_string(value.get<double>()));
	return value.dump();
}

std::string layoutMap(const KeyedEntries &entries)
{
	if (entries.empty())
		return "{}\n";
	std::string s = "{\n";
	for (size_t i = 0; i < entries.size(); ++i)
		s += "  " + OrderedJson(entries[i].first).dump() + ": " + entries[i].second +
		     (i + 1 < entries.size() ? ",\n" : "\n");
	return s + "}\n";
}

std::string layoutMapOfLists(const std::vector<std::pair<std::string, std::vector<std::string>>> &entries)
{
	if (entries.empty())
		return "{}\n";
	std::string s = "{\n";
	for (size_t i = 0; i < entries.size(); ++i) {
		const auto &[key, list] = entries[i];
		s += "  " + OrderedJson(key).dump() + ": ";
		if (list.empty()) {
			s += "[]";
		} else {
			s += "[\n";
			for (size_t j = 0; j < list.size(); ++j)
				s += "    " + list[j] + (j + 1 < list.size() ? ",\n" : "\n");
			s += "  ]";
		}
		s += i + 1 < entries.size() ? ",\n" : "\n";
	}
	return s + "}\n";
}

std::string layoutList(const std::vector<std::string> &entries)
{
	if (entries.empty())
		return "[]\n";
	std::string s = "[\n";
	for (size_t i = 0; i < entries.size(); ++i)
		s += "  " + entries[i] + (i + 1 < entries.size() ? ",\n" : "\n");
	return s + "]\n";
}

} // namespace ihf::bopjson
