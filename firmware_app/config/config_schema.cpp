// SPDX-License-Identifier: MIT
#include "firmware_app/config/config_schema.h"

#include <toml++/toml.h>

#include "firmware_app/config/config_ops.h"

namespace ihf::app {

std::string Range::text() const
{
	constexpr double inf = std::numeric_limits<double>::infinity();
	const auto num = [](double v) {
		return v == std::floor(v) && std::abs(v) < 1e15 ? std::to_string(static_cast<long long>(v)) : detail::showFloat(v);
	};
	// Appended in order: GCC 12 warns falsely (-Wstringop-overflow) on a
	// literal prepended to a temporary string (its insert path).
	std::string out;
	if (lo == -inf && hi == inf)
		return out;
	if (hi == inf) {
		out += loOpen ? "> " : ">= ";
		out += num(lo);
	} else if (lo == -inf) {
		out += "<= ";
		out += num(hi);
	} else {
		out += loOpen ? "(" : "[";
		out += num(lo);
		out += ", ";
		out += num(hi);
		out += "]";
	}
	return out;
}

const KeyDesc *findKey(const Schema &schema, std::string_view table, std::string_view name)
{
	for (const KeyDesc &k : schema.keys)
		if (table == k.table && name == k.name)
			return &k;
	return nullptr;
}

bool knownTable(const Schema &schema, std::string_view table)
{
	for (const KeyDesc &k : schema.keys) {
		const std::string_view t = k.table;
		if (t == table || (t.size() > table.size() && t.starts_with(table) && t[table.size()] == '.'))
			return true;
	}
	return false;
}

std::string showValue(const KeyDesc &key, void *settings)
{
	const Field f = key.field(settings);
	return f.ops->show(f);
}

namespace {

Status readTable(const toml::table &table, const std::string &path, const std::string &file, const Schema &schema,
		 void *settings)
{
	for (const auto &[k, v] : table) {
		const std::string name(k.str());
		if (v.is_table()) {
			const std::string sub = path + "." + name;
			if (!knownTable(schema, sub))
				return makeError(Errc::kParse, file + ": unknown section [" + sub + "]");
			if (Status st = readTable(*v.as_table(), sub, file, schema, settings); !st)
				return st;
			continue;
		}
		const KeyDesc *key = findKey(schema, path, name);
		if (!key)
			return makeError(Errc::kParse, file + ": unknown key " + path + "." + name);
		const Field f = key->field(settings);
		if (const auto problem = f.ops->read(&v, f))
			return makeError(problem->first, file + ": " + path + "." + name + ": " + problem->second);
	}
	return {};
}

} // namespace

Status checkRanges(const std::string &file, const Schema &schema, void *settings)
{
	for (const KeyDesc &key : schema.keys) {
		const Field f = key.field(settings);
		const std::optional<double> v = f.ops->number(f);
		if (v && !key.range.contains(*v))
			return makeError(Errc::kParse, file + ": " + key.path() + ": out of range: " + f.ops->show(f) +
							       (key.range.bounded() ? " (allowed: " + key.range.text() + ")" : ""));
	}
	return {};
}

Status readConfigFile(const std::filesystem::path &path, const Schema &schema, void *settings, const FreeEntry &free)
{
	const std::string file = path.string();
	toml::table root;
	try {
		root = toml::parse_file(file);
	} catch (const toml::parse_error &e) {
		const auto &where = e.source().begin;
		return makeError(Errc::kParse, file + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) +
						       ": " + std::string(e.description()));
	}
	for (const auto &[k, v] : root) {
		const std::string name(k.str());
		bool isFree = false;
		for (const char *t : schema.freeTables)
			isFree = isFree || name == t;
		if (!isFree && !knownTable(schema, name))
			return makeError(Errc::kParse, file + ": unknown section [" + name + "]");
		if (!v.is_table())
			return makeError(Errc::kParse, file + ": " + name + " must be a table");
		if (!isFree) {
			if (Status st = readTable(*v.as_table(), name, file, schema, settings); !st)
				return st;
			continue;
		}
		for (const auto &[entry, value] : *v.as_table()) {
			const std::optional<std::string> text = value.value_exact<std::string>();
			if (Status st = free(name, std::string(entry.str()), text); !st)
				return st;
		}
	}
	return checkRanges(file, schema, settings);
}

namespace {

void collectKeys(const toml::table &table, const std::string &path, std::vector<std::string> &out)
{
	for (const auto &[k, v] : table) {
		const std::string name = (path.empty() ? "" : path + ".") + std::string(k.str());
		if (const toml::table *sub = v.as_table())
			collectKeys(*sub, name, out);
		else
			out.push_back(name);
	}
}

} // namespace

Expected<std::vector<std::string>> keysInFile(const std::filesystem::path &path)
{
	try {
		const toml::table root = toml::parse_file(path.string());
		std::vector<std::string> keys;
		collectKeys(root, "", keys);
		return keys;
	} catch (const toml::parse_error &e) {
		return makeError(Errc::kParse, path.string() + ": " + std::string(e.description()));
	}
}

std::span<const Schema *const> schemas()
{
	static const Schema *const all[] = {&estimateSchema(), &trainSchema(), &deviceSchema()};
	return all;
}

} // namespace ihf::app
