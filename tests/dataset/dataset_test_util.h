// SPDX-License-Identifier: MIT
#pragma once

// Small helpers shared by the dataset tests.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/bop_types.h"

namespace ihf::test {

inline ::testing::AssertionResult relNear(double a, double b, double rel = 1e-9)
{
	double tol = rel * std::max({1.0, std::abs(a), std::abs(b)});
	if (std::abs(a - b) <= tol)
		return ::testing::AssertionSuccess();
	return ::testing::AssertionFailure() << a << " vs " << b << " differ by " << std::abs(a - b);
}

inline ::testing::AssertionResult posesEqual(const Pose &a, const Pose &b)
{
	for (int i = 0; i < 3; ++i) {
		for (int j = 0; j < 3; ++j)
			if (!relNear(a.R(i, j), b.R(i, j)))
				return ::testing::AssertionFailure()
				       << "R(" << i << "," << j << ") " << a.R(i, j) << " vs " << b.R(i, j);
		if (!relNear(a.t(i), b.t(i)))
			return ::testing::AssertionFailure()
			       << "t(" << i << ") " << a.t(i) << " vs " << b.t(i);
	}
	return ::testing::AssertionSuccess();
}

inline std::string readText(const std::filesystem::path &file)
{
	std::ifstream in(file, std::ios::binary);
	std::ostringstream s;
	s << in.rdbuf();
	return s.str();
}

inline void writeText(const std::filesystem::path &file, const std::string &text)
{
	std::ofstream out(file, std::ios::binary);
	out << text;
}

// Every entry of dir (recursively) whose name contains ".tmp-".
inline std::vector<std::string> tempLeftovers(const std::filesystem::path &dir)
{
	std::vector<std::string> found;
	for (const auto &e : std::filesystem::recursive_directory_iterator(dir))
		if (e.path().filename().string().find(".tmp-") != std::string::npos)
			found.push_back(e.path().string());
	return found;
}

} // namespace ihf::test
