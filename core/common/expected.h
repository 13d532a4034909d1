// SPDX-License-Identifier: MIT
#pragma once

// A small std::expected stand-in (C++20 has none). Errors are values: the
// offline paths carry a message naming the file and field at fault; the frame
// path only uses the code and a static reason so it never allocates.

#include <cassert>
#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace ihf {

enum class Errc {
	kInvalidArgument,
	kNotFound,
	kIo,
	kParse,
	kUnsupported,
	kCorrupt,
	kOutOfRange,
	kCapacity,
	kTimeout,
	kNoPose,
};

const char *errcName(Errc code);

// An error's message: a string literal held by pointer, so that the frame
// path can fail without allocating, or an owned string for the offline
// paths that name files, frames and fields. Reads like a const std::string.
class ErrorText
{
public:
	ErrorText() = default;
	// String literals only: a literal lives for the whole program.
	template<std::size_t N>
	ErrorText(const char (&literal)[N]) : literal_(literal) {}
	// A writable buffer (snprintf) would dangle: copy it into a std::string.
	template<std::size_t N>
	ErrorText(char (&buffer)[N]) = delete;
	ErrorText(std::string text) : literal_(nullptr), owned_(std::move(text)) {}

	const char *c_str() const { return literal_ ? literal_ : owned_.c_str(); }
	std::string_view view() const { return literal_ ? std::string_view(literal_) : std::string_view(owned_); }
	operator std::string_view() const { return view(); }
	operator std::string() const { return std::string(view()); }
	std::size_t find(std::string_view s, std::size_t pos = 0) const { return view().find(s, pos); }
	// True when the text is a literal held by pointer (no allocation).
	bool isLiteral() const { return literal_ != nullptr; }

private:
	const char *literal_ = "";
	std::string owned_;
};

inline std::string operator+(const std::string &a, const ErrorText &b) { return a + std::string(b.view()); }
inline std::string operator+(const char *a, const ErrorText &b) { return std::string(a) + std::string(b.view()); }
inline std::string operator+(const ErrorText &a, const std::string &b) { return std::string(a.view()) + b; }
inline std::string operator+(const ErrorText &a, const char *b) { return std::string(a.view()) + b; }
inline bool operator==(const ErrorText &a, std::string_view b) { return a.view() == b; }
inline std::ostream &operator<<(std::ostream &os, const ErrorText &t) { return os << t.view(); }

struct Error {
	Errc code = Errc::kInvalidArgument;
	ErrorText message;
};

inline Error makeError(Errc code, ErrorText message)
{
	return Error{code, std::move(message)};
}

template<typename T>
class [[nodiscard]] Expected
{
public:
	Expected(T value) : v_(std::move(value)) {}
	Expected(Error error) : v_(std::move(error)) {}

	bool ok() const { return v_.index() == 0; }
	explicit operator bool() const { return ok(); }

	T &value() & { assert(ok()); return std::get<0>(v_); }
	const T &value() const & { assert(ok()); return std::get<0>(v_); }
	T &&value() && { assert(ok()); return std::get<0>(std::move(v_)); }
	T &operator*() & { return value(); }
	const T &operator*() const & { return value(); }
	T *operator->() { return &value(); }
	const T *operator->() const { return &value(); }

	const Error &error() const { assert(!ok()); return std::get<1>(v_); }

private:
	std::variant<T, Error> v_;
};

template<>
class [[nodiscard]] Expected<void>
{
public:
	Expected() = default;
	Expected(Error error) : error_(std::move(error)), ok_(false) {}

	bool ok() const { return ok_; }
	explicit operator bool() const { return ok_; }
	const Error &error() const { assert(!ok_); return error_; }

private:
	Error error_;
	bool ok_ = true;
};

using Status = Expected<void>;

inline const char *errcName(Errc code)
{
	switch (code) {
	case Errc::kInvalidArgument: return "invalid argument";
	case Errc::kNotFound: return "not found";
	case Errc::kIo: return "I/O error";
	case Errc::kParse: return "parse error";
	case Errc::kUnsupported: return "unsupported";
	case Errc::kCorrupt: return "corrupt";
	case Errc::kOutOfRange: return "out of range";
	case Errc::kCapacity: return "capacity exceeded";
	case Errc::kTimeout: return "timeout";
	case Errc::kNoPose: return "no pose";
	}
	return "unknown";
}

} // namespace ihf
