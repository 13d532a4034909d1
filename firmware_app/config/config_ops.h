// SPDX-License-Identifier: MIT
#pragma once

// How each C++ type of a setting is read from TOML and shown as TOML
// (config_schema.h's FieldOps). Included where descriptor tables are
// declared (config_keys.cpp): it pulls in toml++.

#include <charconv>
#include <cmath>
#include <string>
#include <utility>

#include <toml++/toml.h>

#include "firmware_app/config/config_schema.h"

namespace ihf::app {

namespace detail {

using ReadError = std::optional<std::pair<Errc, std::string>>;

template<typename T>
struct IsOptional : std::false_type {};
template<typename T>
struct IsOptional<std::optional<T>> : std::true_type {
	using Value = T;
};

// Types a name list can stand for: enums, bools, ints, optional enums.
template<typename T>
constexpr bool kNameable = std::is_enum_v<T> || std::is_integral_v<T>;
template<typename T>
constexpr bool kNameable<std::optional<T>> = std::is_enum_v<T>;

inline ReadError expected(const char *what)
{
	return std::pair{Errc::kParse, std::string("expected ") + what};
}

// The shortest text that reads back as the same value, always a TOML float.
template<typename F>
std::string showFloat(F v)
{
	if (std::isnan(v))
		return "nan";
	if (std::isinf(v))
		return v > 0 ? "inf" : "-inf";
	char buf[64];
	const auto r = std::to_chars(buf, buf + sizeof buf, v);
	std::string s(buf, r.ptr);
	if (s.find_first_of(".e") == std::string::npos)
		s += ".0";
	return s;
}

inline std::string quoted(const std::string &s)
{
	std::string q = "\"";
	for (char c : s) {
		if (c == '"' || c == '\\')
			q += '\\';
		q += c;
	}
	return q + "\"";
}

// Enumerated settings: the value as an int, and back.
template<typename T>
int asInt(const T &v)
{
	if constexpr (IsOptional<T>::value)
		return v ? static_cast<int>(*v) : -1;
	else
		return static_cast<int>(v);
}
template<typename T>
void fromInt(T &out, int v)
{
	if constexpr (IsOptional<T>::value) {
		if (v < 0)
			out.reset();
		else
			out = static_cast<typename IsOptional<T>::Value>(v);
	} else if constexpr (std::is_same_v<T, bool>) {
		out = v != 0;
	} else {
		out = static_cast<T>(v);
	}
}

template<typename T>
ReadError readNamed(const toml::node &node, const Field &f)
{
	const auto s = node.value_exact<std::string>();
	if (!s)
		return expected("a string");
	for (const Named &n : f.names)
		if (*s == n.name) {
			fromInt(*static_cast<T *>(f.p), n.value);
			return std::nullopt;
		}
	std::string allowed;
	for (const Named &n : f.names)
		allowed += std::string(allowed.empty() ? "" : ", ") + "\"" + n.name + "\"";
	return std::pair{Errc::kParse, "unknown value \"" + *s + "\" (allowed: " + allowed + ")"};
}

template<typename T>
ReadError read(const void *from, const Field &f)
{
	const toml::node &node = *static_cast<const toml::node *>(from);
	T &out = *static_cast<T *>(f.p);
	if constexpr (kNameable<T>)
		if (!f.names.empty())
			return readNamed<T>(node, f);
	if constexpr (IsOptional<T>::value) {
		// A setting that may be unset: its value type read, then set.
		typename IsOptional<T>::Value v{};
		const Field inner{&v, f.ops, {}};
		if (auto problem = read<typename IsOptional<T>::Value>(from, inner))
			return problem;
		out = v;
	} else if constexpr (std::is_same_v<T, bool>) {
		const auto v = node.value_exact<bool>();
		if (!v)
			return expected("a boolean");
		out = *v;
	} else if constexpr (std::is_integral_v<T>) {
		// TOML integers are 64-bit: a value the setting's type cannot hold
		// is an error, never wrapped into range.
		const auto v = node.value_exact<int64_t>();
		if (!v)
			return expected("an integer");
		if (!std::in_range<T>(*v))
			return std::pair{Errc::kOutOfRange, std::to_string(*v) + " is out of range [" +
								    std::to_string(std::numeric_limits<T>::min()) + ", " +
								    std::to_string(std::numeric_limits<T>::max()) + "]"};
		out = static_cast<T>(*v);
	} else if constexpr (std::is_floating_point_v<T>) {
		const auto v = node.value<double>();
		if (!v)
			return expected("a number");
		if (std::isfinite(*v) && std::abs(*v) > std::numeric_limits<T>::max())
			return std::pair{Errc::kOutOfRange, std::to_string(*v) + " is outside the range of a " +
								    std::to_string(8 * sizeof(T)) + "-bit float"};
		out = static_cast<T>(*v);
	} else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::filesystem::path>) {
		const auto v = node.value_exact<std::string>();
		if (!v)
			return expected("a string");
		out = *v;
	} else if constexpr (std::is_same_v<T, std::vector<float>>) {
		const toml::array *arr = node.as_array();
		if (!arr)
			return expected("an array of numbers");
		std::vector<float> values;
		for (const auto &el : *arr) {
			const auto v = el.value<double>();
			if (!v)
				return expected("an array of numbers");
			values.push_back(static_cast<float>(*v));
		}
		out = std::move(values);
	} else {
		return expected("one of its names"); // an enumerated setting is read by its names
	}
	return std::nullopt;
}

template<typename T>
std::string show(const Field &f)
{
	const T &v = *static_cast<const T *>(f.p);
	if constexpr (kNameable<T>)
		if (!f.names.empty()) {
			const int i = asInt(v);
			for (const Named &n : f.names)
				if (n.value == i)
					return quoted(n.name);
			return "?";
		}
	if constexpr (IsOptional<T>::value) {
		if (!v)
			return ""; // unset
		typename IsOptional<T>::Value inner = *v;
		return show<typename IsOptional<T>::Value>(Field{&inner, f.ops, {}});
	} else if constexpr (std::is_same_v<T, bool>) {
		return v ? "true" : "false";
	} else if constexpr (std::is_integral_v<T>) {
		return std::to_string(v);
	} else if constexpr (std::is_floating_point_v<T>) {
		return showFloat(v);
	} else if constexpr (std::is_same_v<T, std::string>) {
		return quoted(v);
	} else if constexpr (std::is_same_v<T, std::filesystem::path>) {
		return quoted(v.string());
	} else if constexpr (std::is_same_v<T, std::vector<float>>) {
		std::string s = "[";
		for (size_t i = 0; i < v.size(); ++i)
			s += (i ? ", " : "") + showFloat(v[i]);
		return s + "]";
	} else {
		return "?";
	}
}

template<typename T>
std::optional<double> number(const Field &f)
{
	if constexpr (IsOptional<T>::value) {
		const T &v = *static_cast<const T *>(f.p);
		if (!v || !f.names.empty())
			return std::nullopt;
		typename IsOptional<T>::Value inner = *v;
		return number<typename IsOptional<T>::Value>(Field{&inner, f.ops, {}});
	} else if constexpr ((std::is_integral_v<T> && !std::is_same_v<T, bool>) || std::is_floating_point_v<T>)
		return static_cast<double>(*static_cast<const T *>(f.p));
	else
		return std::nullopt;
}

template<typename T>
const char *typeName()
{
	if constexpr (IsOptional<T>::value)
		return typeName<typename IsOptional<T>::Value>();
	else if constexpr (std::is_same_v<T, bool>)
		return "boolean";
	else if constexpr (std::is_integral_v<T>)
		return "integer";
	else if constexpr (std::is_floating_point_v<T>)
		return "number";
	else if constexpr (std::is_same_v<T, std::vector<float>>)
		return "array of numbers";
	else
		return "string";
}

} // namespace detail

template<typename T>
const FieldOps &opsFor()
{
	static const FieldOps ops{detail::typeName<T>(), &detail::read<T>, &detail::show<T>, &detail::number<T>};
	return ops;
}

} // namespace ihf::app
