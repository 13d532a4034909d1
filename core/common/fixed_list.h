// SPDX-License-Identifier: MIT
#pragma once

// A list of at most a fixed number of elements that never touches the heap.
//
// FixedListBase<T> is the list without its capacity: it works on storage
// someone else owns (an arena span, or FixedList's own array), so that a
// function taking FixedListBase<T> & is compiled once per element type, not
// once per capacity (ETL's ivector). FixedList<T, N> carries its storage
// inline; FixedListBase<T>(span) wraps a buffer carved from an arena.
//
// Appending to a full list is a checked error (Errc::kCapacity), never a
// write past the end. insertRanked() keeps a list sorted best first as a
// top-N list: a full list drops its worst element, or the new one when it
// is not better than that.
//
// Elements are assigned, not constructed in place: T must be default
// constructible and copy assignable (the storage holds capacity elements).

#include <algorithm>
#include <array>
#include <cassert>
#include <cstddef>
#include <span>

#include "core/common/expected.h"

namespace ihf {

template<typename T>
class FixedListBase
{
public:
	FixedListBase() = default;
	explicit FixedListBase(std::span<T> storage) : data_(storage.data()), capacity_(storage.size()) {}
	FixedListBase(const FixedListBase &) = delete;
	FixedListBase &operator=(const FixedListBase &) = delete;

	size_t size() const { return size_; }
	size_t capacity() const { return capacity_; }
	bool empty() const { return size_ == 0; }
	bool full() const { return size_ == capacity_; }

	T &operator[](size_t i)
	{
		assert(i < size_);
		return data_[i];
	}
	const T &operator[](size_t i) const
	{
		assert(i < size_);
		return data_[i];
	}
	T &front() { return (*this)[0]; }
	const T &front() const { return (*this)[0]; }
	T &back() { return (*this)[size_ - 1]; }
	const T &back() const { return (*this)[size_ - 1]; }

	T *begin() { return data_; }
	T *end() { return data_ + size_; }
	const T *begin() const { return data_; }
	const T *end() const { return data_ + size_; }
	std::span<T> items() { return {data_, size_}; }
	std::span<const T> items() const { return {data_, size_}; }

	void clear() { size_ = 0; }

	// Empties the list and makes it use `storage` (its capacity: the span's
	// size).
	void setStorage(std::span<T> storage)
	{
		data_ = storage.data();
		capacity_ = storage.size();
		size_ = 0;
	}

	// Appends value; Errc::kCapacity when the list is full.
	Status pushBack(const T &value)
	{
		if (full())
			return makeError(Errc::kCapacity, "fixed list full");
		data_[size_++] = value;
		return {};
	}

	// Inserts value before element `at` (at <= size()); Errc::kCapacity
	// when the list is full.
	Status insert(size_t at, const T &value)
	{
		if (full())
			return makeError(Errc::kCapacity, "fixed list full");
		assert(at <= size_);
		std::move_backward(data_ + at, data_ + size_, data_ + size_ + 1);
		data_[at] = value;
		++size_;
		return {};
	}

	// Removes element `at`; the later ones move up.
	void erase(size_t at)
	{
		assert(at < size_);
		std::move(data_ + at + 1, data_ + size_, data_ + at);
		--size_;
	}

	// Drops the elements from `n` on (n >= size(): none).
	void truncate(size_t n) { size_ = std::min(size_, n); }

private:
	T *data_ = nullptr;
	size_t capacity_ = 0;
	size_t size_ = 0;
};

template<typename T, size_t N>
class FixedList : public FixedListBase<T>
{
public:
	FixedList() { this->setStorage(storage_); }
	FixedList(const FixedList &other) : FixedList() { copyFrom(other); }
	FixedList &operator=(const FixedList &other)
	{
		if (this != &other) {
			this->clear();
			copyFrom(other);
		}
		return *this;
	}

private:
	void copyFrom(const FixedList &other)
	{
		for (const T &v : other)
			static_cast<void>(this->pushBack(v));
	}

	std::array<T, N> storage_{};
};

// Inserts value into a list sorted best first by key (higher is better),
// after the elements whose key is not lower (so equal keys keep their order
// of arrival). A full list drops its last element to make room; when the
// value would go past the end, nothing changes. Returns whether value was
// inserted.
template<typename T, typename Key>
bool insertRanked(FixedListBase<T> &list, const T &value, Key &&key)
{
	const auto k = key(value);
	size_t pos = list.size();
	while (pos > 0 && key(list[pos - 1]) < k)
		--pos;
	if (pos >= list.capacity())
		return false;
	if (list.full())
		list.truncate(list.size() - 1);
	static_cast<void>(list.insert(pos, value));
	return true;
}

} // namespace ihf
