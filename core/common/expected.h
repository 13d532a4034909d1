// SPDX-License-Identifier: MIT
#pragma once

// A small std::expected stand-in (C++20 has none). Errors are values: the
// offline paths carry a message naming the file and field at fault; the frame
// path only uses the code and a static reason so it never allocates.

#include <cassert>
#include <string>
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

struct Error {
	Errc code = Errc::kInvalidArgument;
	std::string message;
};

inline Error makeError(Errc code, std::string message)
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
