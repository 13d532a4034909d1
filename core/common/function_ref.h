// SPDX-License-Identifier: MIT
#pragma once

// A non-owning reference to a callable: a pointer to it and a trampoline.
// std::function may allocate to hold a capture; the frame path may not, and
// a call that outlives its callable is not needed there.

#include <type_traits>
#include <utility>

namespace ihf {

template<typename Signature>
class FunctionRef;

template<typename R, typename... Args>
class FunctionRef<R(Args...)>
{
public:
	FunctionRef() = default;

	template<typename F, typename = std::enable_if_t<!std::is_same_v<std::decay_t<F>, FunctionRef>>>
	FunctionRef(F &&f) // NOLINT(google-explicit-constructor): used like a lambda parameter
		: obj_(const_cast<void *>(static_cast<const void *>(&f))),
		  call_([](void *obj, Args... args) -> R {
			  return (*static_cast<std::remove_reference_t<F> *>(obj))(std::forward<Args>(args)...);
		  })
	{
	}

	R operator()(Args... args) const { return call_(obj_, std::forward<Args>(args)...); }
	explicit operator bool() const { return call_ != nullptr; }

private:
	void *obj_ = nullptr;
	R (*call_)(void *, Args...) = nullptr;
};

} // namespace ihf
