// SPDX-License-Identifier: MIT
#pragma once

// One descriptor per configuration key: where it lives in the TOML (table
// and name), the setting it sets, its range, what it means and whether a
// user tunes it or only an expert. The descriptor tables (config_keys.cpp)
// drive the TOML reader, the range checks, `ihf config` and
// docs/configuration.md; the default of a key is the value of its setting
// in a default-constructed settings struct, so it is declared once, in
// code.
//
// A profile (the settings inside a frame budget, a tight or a short share
// of it, a lean search, a refinement iteration, modal boxes) is a table of
// sparse overrides named after the profile, holding copies of the base
// tables it changes: [budget.view_search] refine_top overrides
// [view_search] refine_top inside a budget.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/common/expected.h"

namespace ihf::app {

enum class Audience : uint8_t {
	kUser,   // a setting a user tunes (kept in the shipped file)
	kExpert, // documented, its default in code
	kSite,   // the installation's own (paths, devices): the shipped value is an example
};

// Inclusive bounds unless open; numbers only.
struct Range {
	double lo = -std::numeric_limits<double>::infinity();
	double hi = std::numeric_limits<double>::infinity();
	bool loOpen = false;
	bool contains(double v) const { return (loOpen ? v > lo : v >= lo) && v <= hi; }
	bool bounded() const { return lo > -std::numeric_limits<double>::infinity() || hi < std::numeric_limits<double>::infinity(); }
	std::string text() const;
};
inline constexpr Range kAny{};
constexpr Range atLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false}; }
constexpr Range above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true}; }
constexpr Range within(double lo, double hi) { return {lo, hi, false}; }

// A named value of an enumerated setting ("fixed" -> PartKind::kFixed).
struct Named {
	const char *name;
	int value;
};

struct Field;

// How a setting of one C++ type is read from TOML and shown.
struct FieldOps {
	const char *type; // "integer", "number", "boolean", "string", ...
	// Sets the field from a toml::node; an error message (without the
	// key) and its code when the node does not fit.
	std::optional<std::pair<Errc, std::string>> (*read)(const void *node, const Field &f);
	std::string (*show)(const Field &f);               // as TOML
	std::optional<double> (*number)(const Field &f);   // for the range check
};

struct Field {
	void *p;
	const FieldOps *ops;
	std::span<const Named> names; // enumerated settings: their names
};

template<typename T>
const FieldOps &opsFor();

template<typename T>
Field field(T &value)
{
	return {&value, &opsFor<T>(), {}};
}
// An enumerated setting (an enum, a bool or an optional enum, whose
// nullopt is named "").
template<typename T>
Field field(T &value, std::span<const Named> names)
{
	return {&value, &opsFor<T>(), names};
}

struct KeyDesc {
	const char *table; // "refinement", or a profile's "budget.view_search"
	const char *name;
	Field (*field)(void *settings);
	Range range;
	Audience audience;
	const char *meaning;
	std::string path() const { return std::string(table) + "." + name; }
};

// What a table is for, in the reference (docs/configuration.md).
struct TableNote {
	const char *table;
	const char *note;
};

// A configuration: its keys, and its tables whose keys are free (read by
// their loader: [objects] of the device config).
struct Schema {
	const char *kind; // "estimate", "train", "device"
	const char *file; // the shipped file, relative to the source tree
	const char *command; // what reads it
	std::span<const KeyDesc> keys;
	std::span<const char *const> freeTables;
	// The free tables' entries as documented ("<id>").
	std::span<const KeyDesc> freeKeys;
	std::span<const TableNote> notes;
	// A default-constructed settings struct of this kind, and its deletion.
	void *(*make)();
	void (*destroy)(void *);
	// The kind's loader (pipeline_config.h) into such a struct: a file's
	// settings after everything the loader derives from them.
	Status (*load)(const std::filesystem::path &path, void *settings);
};

const Schema &estimateSchema();
const Schema &trainSchema();
const Schema &deviceSchema();
std::span<const Schema *const> schemas();

// An entry of a free table: its key and its value when that is a string.
using FreeEntry = std::function<Status(const std::string &table, const std::string &key,
				       const std::optional<std::string> &text)>;

// Reads a TOML file into settings (of the schema's type), then checks
// every key's range. Syntax errors, unknown tables and keys, wrongly typed
// values and values out of their range are errors naming the file, table
// and key.
Status readConfigFile(const std::filesystem::path &path, const Schema &schema, void *settings,
		      const FreeEntry &free = {});
// The range check of every key (a file's or a default), in schema order.
Status checkRanges(const std::string &file, const Schema &schema, void *settings);
// Whether a table (or a profile holding tables) has keys in the schema.
bool knownTable(const Schema &schema, std::string_view table);

// The keys a TOML file holds ("table.name", free tables' entries too), in
// the file's order.
Expected<std::vector<std::string>> keysInFile(const std::filesystem::path &path);

// A key's value as TOML.
std::string showValue(const KeyDesc &key, void *settings);

// A key described by its table and name; nullptr if none.
const KeyDesc *findKey(const Schema &schema, std::string_view table, std::string_view name);

// A default-constructed settings struct of the schema's kind.
class SettingsOf
{
public:
	explicit SettingsOf(const Schema &schema) : schema_(&schema), p_(schema.make()) {}
	~SettingsOf() { schema_->destroy(p_); }
	SettingsOf(const SettingsOf &) = delete;
	SettingsOf &operator=(const SettingsOf &) = delete;
	void *get() const { return p_; }

private:
	const Schema *schema_;
	void *p_;
};

} // namespace ihf::app
