// SPDX-License-Identifier: MIT
#pragma once

// Internal helpers of the BOP readers/writers: typed field access on
// nlohmann::json that reports the file and JSON path of a bad field
// (e.g. `scene_gt.json: "3"[1].cam_t_m2c: expected 3 numbers, got 2`), and a
// deterministic, compact-per-entry JSON layout for the writers.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/common/expected.h"

namespace ihf::bopjson {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

// Where a value sits: file plus JSON path, for error messages.
class JsonPath
{
public:
	explicit JsonPath(const std::filesystem::path &file) : file_(&file) {}

	JsonPath key(std::string_view key) const;    // map key:    "3"
	JsonPath field(std::string_view name) const; // named field: .cam_K
	JsonPath index(size_t i) const;              // list entry: [1]

	const std::filesystem::path &file() const { return *file_; }
	const std::string &str() const { return path_; }
	Error error(Errc code, const std::string &what) const;

private:
	const std::filesystem::path *file_;
	std::string path_;
};

// Reads and parses a whole file. Missing file: kNotFound; malformed: kParse
// with the byte offset and line/column from the parser.
Expected<Json> loadJson(const std::filesystem::path &file);

Status expectObject(const Json &value, const JsonPath &at);
Status expectArray(const Json &value, const JsonPath &at);

// Conversions of one value; 'at' is the value's own path.
Status asNumber(const Json &value, const JsonPath &at, double &out);
Status asInt(const Json &value, const JsonPath &at, int &out);
Status asNumbers(const Json &value, const JsonPath &at, double *out, size_t count);
Status asInts(const Json &value, const JsonPath &at, int *out, size_t count);

// Required fields of the object 'obj' found at 'at'.
Status readNumber(const Json &obj, const JsonPath &at, const char *name, double &out);
Status readInt(const Json &obj, const JsonPath &at, const char *name, int &out);
Status readNumbers(const Json &obj, const JsonPath &at, const char *name, double *out,
		   size_t count);
Status readInts(const Json &obj, const JsonPath &at, const char *name, int *out, size_t count);

// A map key that is a decimal id ("3", "000012"), non-negative.
Expected<int> parseIdKey(const std::string &key, const JsonPath &at);

// Single-line JSON with ", " and ": " separators. Non-finite numbers (which
// JSON cannot hold) are an error naming the path.
Expected<std::string> compactJson(const OrderedJson &value, const JsonPath &at);

// Layouts used by all BOP writers: one map entry (or list entry) per line;
// nested lists of entries one per line too.
using KeyedEntries = std::vector<std::pair<std::string, std::string>>;
std::string layoutMap(const KeyedEntries &entries);
std::string layoutMapOfLists(const std::vector<std::pair<std::string, std::vector<std::string>>> &entries);
std::string layoutList(const std::vector<std::string> &entries);

} // namespace ihf::bopjson
