// SPDX-License-Identifier: MIT
// BOP results CSV: "scene_id,im_id,obj_id,score,R,t,time", R nine numbers
// row-major and t three numbers (mm), each separated by spaces.

#include <array>
#include <charconv>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_io.h"

namespace ihf {

namespace {

constexpr std::string_view kHeader = "scene_id,im_id,obj_id,score,R,t,time";
constexpr std::array<const char *, 7> kColumns = {"scene_id", "im_id", "obj_id", "score",
						  "R", "t", "time"};

std::string_view trim(std::string_view s)
{
	while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
		s.remove_prefix(1);
	while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
		s.remove_suffix(1);
	return s;
}

template<typename T>
bool parseWhole(std::string_view s, T &out)
{
	s = trim(s);
	if (s.empty())
		return false;
	auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
	return ec == std::errc() && ptr == s.data() + s.size();
}

// One CSV field with its position, for error messages.
struct Cell {
	std::string_view text;
	size_t line;
	size_t column; // 1-based character column of the field start
	size_t index;  // 0-based field index
};

class CsvErrors
{
public:
	explicit CsvErrors(const fs::path &file) : file_(file) {}

	Error at(size_t line, size_t column, const std::string &what) const
	{
		return makeError(Errc::kParse, file_.string() + ":" + std::to_string(line) + ":" +
						       std::to_string(column) + ": " + what);
	}
	Error at(const Cell &c, const std::string &what) const
	{
		return at(c.line, c.column, "column " + std::to_string(c.index + 1) + " (" +
						   kColumns[c.index] + "): " + what);
	}

private:
	const fs::path &file_;
};

Status parseInt(const Cell &c, const CsvErrors &err, int &out)
{
	if (!parseWhole(c.text, out))
		return err.at(c, "expected an integer, got \"" + std::string(trim(c.text)) + "\"");
	return {};
}

Status parseNumber(const Cell &c, const CsvErrors &err, double &out)
{
	if (!parseWhole(c.text, out))
		return err.at(c, "expected a number, got \"" + std::string(trim(c.text)) + "\"");
	return {};
}

// count space-separated numbers in one field.
Status parseNumbers(const Cell &c, const CsvErrors &err, double *out, size_t count)
{
	std::string_view s = c.text;
	size_t n = 0;
	while (true) {
		size_t start = s.find_first_not_of(" \t\r");
		if (start == std::string_view::npos)
			break;
		s.remove_prefix(start);
		size_t end = s.find_first_of(" \t\r");
		std::string_view token = s.substr(0, end);
		if (n < count && !parseWhole(token, out[n])) {
			// Appended, not "literal" + string: GCC 12 warns falsely on that at -O3.
			std::string what = "value ";
			what.append(std::to_string(n + 1)).append(": expected a number, got \"").append(token).append("\"");
			return err.at(c, what);
		}
		++n;
		if (end == std::string_view::npos)
			break;
		s.remove_prefix(end);
	}
	if (n != count) {
		std::string what = "expected ";
		what.append(std::to_string(count)).append(" numbers, got ").append(std::to_string(n));
		return err.at(c, what);
	}
	return {};
}

void appendNumber(std::string &out, double v)
{
	// Shortest text that reads back to the same double.
	char buf[32];
	auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), v);
	out.append(buf, ec == std::errc() ? ptr : buf);
}

} // namespace

Expected<std::vector<ResultRow>> readResultsCsv(const fs::path &file)
{
	std::error_code ec;
	if (!fs::exists(file, ec))
		return makeError(Errc::kNotFound, file.string() + ": file not found");
	std::ifstream in(file, std::ios::binary);
	if (!in)
		return makeError(Errc::kIo, file.string() + ": cannot open for reading");
	std::ostringstream buf;
	buf << in.rdbuf();
	const std::string text = buf.str();

	CsvErrors err(file);
	std::vector<ResultRow> rows;
	std::string_view rest = text;
	if (rest.substr(0, 3) == "\xEF\xBB\xBF") // UTF-8 byte order mark
		rest.remove_prefix(3);

	size_t lineNo = 0;
	bool sawHeader = false;
	while (!rest.empty()) {
		size_t nl = rest.find('\n');
		std::string_view line = rest.substr(0, nl);
		rest = nl == std::string_view::npos ? std::string_view{} : rest.substr(nl + 1);
		++lineNo;

		if (!sawHeader) {
			if (trim(line) != kHeader) {
				std::string what = "expected header \""; // appended, as above
				what.append(kHeader).append("\", got \"").append(trim(line)).append("\"");
				return err.at(lineNo, 1, what);
			}
			sawHeader = true;
			continue;
		}
		if (trim(line).empty())
			continue;

		std::array<Cell, 7> cells;
		size_t count = 0;
		size_t pos = 0;
		while (true) {
			size_t comma = line.find(',', pos);
			if (count < cells.size())
				cells[count] = {line.substr(pos, comma == std::string_view::npos ?
								   std::string_view::npos : comma - pos),
						lineNo, pos + 1, count};
			++count;
			if (comma == std::string_view::npos)
				break;
			pos = comma + 1;
		}
		if (count != cells.size())
			return err.at(lineNo, 1, "expected 7 columns (" + std::string(kHeader) +
							 "), got " + std::to_string(count));

		ResultRow row;
		double r[9], t[3];
		if (Status s = parseInt(cells[0], err, row.sceneId); !s)
			return s.error();
		if (Status s = parseInt(cells[1], err, row.imId); !s)
			return s.error();
		if (Status s = parseInt(cells[2], err, row.objId); !s)
			return s.error();
		if (Status s = parseNumber(cells[3], err, row.score); !s)
			return s.error();
		if (Status s = parseNumbers(cells[4], err, r, 9); !s)
			return s.error();
		if (Status s = parseNumbers(cells[5], err, t, 3); !s)
			return s.error();
		if (Status s = parseNumber(cells[6], err, row.time); !s)
			return s.error();
		for (int i = 0; i < 3; ++i) {
			for (int j = 0; j < 3; ++j)
				row.pose.R(i, j) = r[3 * i + j];
			row.pose.t(i) = t[i];
		}
		rows.push_back(row);
	}
	if (!sawHeader)
		return err.at(1, 1, "empty file, expected header \"" + std::string(kHeader) + "\"");
	return rows;
}

Status writeResultsCsv(const fs::path &file, const std::vector<ResultRow> &rows)
{
	std::string out(kHeader);
	out += '\n';
	for (const ResultRow &row : rows) {
		out += std::to_string(row.sceneId) + ',' + std::to_string(row.imId) + ',' +
		       std::to_string(row.objId) + ',';
		appendNumber(out, row.score);
		out += ',';
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j) {
				if (i || j)
					out += ' ';
				appendNumber(out, row.pose.R(i, j));
			}
		out += ',';
		for (int i = 0; i < 3; ++i) {
			if (i)
				out += ' ';
			appendNumber(out, row.pose.t(i));
		}
		out += ',';
		appendNumber(out, row.time);
		out += '\n';
	}
	return writeFileAtomic(file, out);
}

} // namespace ihf
