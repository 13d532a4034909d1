// SPDX-License-Identifier: MIT
#include "core/eval/run_poses.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <string_view>

#include <nlohmann/json.hpp>

namespace ihf {

namespace {

using Json = nlohmann::json;

// Parses the fields of one line; `where` ("FILE line N: ") starts each error.
class LineReader
{
public:
	LineReader(const Json &line, std::string where) : json_(line), where_(std::move(where)) {}

	Error error(const std::string &what) const { return makeError(Errc::kParse, where_ + what); }

	bool has(const char *field) const { return json_.contains(field); }

	Expected<uint64_t> frame() const
	{
		const Json &v = json_.at("frame");
		if (!v.is_number_unsigned())
			return error("\"frame\" is not a non-negative integer");
		return v.get<uint64_t>();
	}

	Expected<int> objId() const
	{
		const Json &v = json_.at("obj_id");
		if (!v.is_number_unsigned() || v.get<uint64_t>() == 0 ||
		    v.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int>::max()))
			return error("\"obj_id\" is not a positive integer");
		return static_cast<int>(v.get<uint64_t>());
	}

	// The N numbers of an array field, finite.
	template<int N>
	Expected<Eigen::Matrix<double, N, 1>> numbers(const char *field, const char *meaning) const
	{
		const Json &v = json_.at(field);
		Eigen::Matrix<double, N, 1> out;
		bool good = v.is_array() && v.size() == static_cast<size_t>(N);
		for (int i = 0; good && i < N; ++i) {
			const Json &x = v[static_cast<size_t>(i)];
			good = x.is_number() && std::isfinite(x.get<double>());
			if (good)
				out(i) = x.get<double>();
		}
		if (!good) {
			// Appended piecewise: GCC 12 warns falsely on "\"" + std::string(...).
			std::string what = "\"";
			what += field;
			what += "\" is not " + std::to_string(N) + " numbers (";
			what += meaning;
			what += ")";
			return error(what);
		}
		return out;
	}

private:
	const Json &json_;
	std::string where_;
};

Expected<RunPoseLine> readErrorLine(const LineReader &in, const Json &json, RunPoseLine line)
{
	if (!json.at("error").is_string())
		return in.error("\"error\" is not a string");
	line.error = json.at("error").get<std::string>();
	if (in.has("frame")) {
		Expected<uint64_t> frame = in.frame();
		if (!frame)
			return frame.error();
		line.frame = *frame;
	}
	if (in.has("obj_id")) {
		Expected<int> objId = in.objId();
		if (!objId)
			return objId.error();
		line.objId = *objId;
	}
	return line;
}

Expected<RunPoseLine> readPoseLine(const LineReader &in, RunPoseLine line)
{
	for (const char *field : {"frame", "obj_id", "R", "t"}) {
		if (!in.has(field)) {
			std::string what = "no \"";
			what += field;
			what += "\" (a pose line has frame, obj_id, R and t; an error line has \"error\")";
			return in.error(what);
		}
	}
	Expected<uint64_t> frame = in.frame();
	if (!frame)
		return frame.error();
	Expected<int> objId = in.objId();
	if (!objId)
		return objId.error();
	Expected<Eigen::Matrix<double, 9, 1>> r = in.numbers<9>("R", "a row-major rotation");
	if (!r)
		return r.error();
	Expected<Eigen::Matrix<double, 3, 1>> t = in.numbers<3>("t", "millimetres");
	if (!t)
		return t.error();
	Pose pose;
	for (int i = 0; i < 9; ++i)
		pose.R(i / 3, i % 3) = (*r)(i);
	pose.t = *t;
	line.frame = *frame;
	line.objId = *objId;
	line.pose = pose;
	return line;
}

Expected<RunPoseLine> readLine(const std::filesystem::path &file, size_t number, std::string_view text)
{
	const std::string where = file.string() + " line " + std::to_string(number) + ": ";
	const Json json = Json::parse(text.begin(), text.end(), nullptr, false);
	if (json.is_discarded())
		return makeError(Errc::kParse, where + "not JSON");
	if (!json.is_object())
		return makeError(Errc::kParse, where + "not a JSON object");
	const LineReader in(json, where);
	RunPoseLine line;
	line.line = number;
	if (in.has("error"))
		return readErrorLine(in, json, std::move(line));
	return readPoseLine(in, std::move(line));
}

bool blank(std::string_view text)
{
	return text.find_first_not_of(" \t\r") == std::string_view::npos;
}

} // namespace

Expected<std::vector<RunPoseLine>> readRunPoses(const std::filesystem::path &file)
{
	std::ifstream in(file, std::ios::binary);
	if (!in)
		return makeError(Errc::kIo, file.string() + ": cannot open the poses");
	std::vector<RunPoseLine> lines;
	std::string text;
	for (size_t number = 1; std::getline(in, text); ++number) {
		if (blank(text))
			continue;
		Expected<RunPoseLine> line = readLine(file, number, text);
		if (!line)
			return line.error();
		lines.push_back(std::move(*line));
	}
	if (in.bad())
		return makeError(Errc::kIo, file.string() + ": reading the poses failed");
	return lines;
}

} // namespace ihf
