// SPDX-License-Identifier: MIT
// PLY reading (ply_writer.cpp writes). The whole file is read into memory (BOP models are
// a few MB), the header is parsed into a list of elements, and the body is
// walked element by element: ASCII one instance per line, binary by the
// declared type sizes (little or big endian). Only vertex positions/normals
// and face index lists are kept; every other property and element is skipped.

#include "core/geometry/ply_loader.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace ihf {

namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyProperty {
	std::string name;
	bool isList = false;
	PlyType type = PlyType::kFloat32; // item type for lists
	PlyType countType = PlyType::kUint8;
};

struct PlyElement {
	std::string name;
	size_t count = 0;
	std::vector<PlyProperty> properties;
};

struct PlyHeader {
	PlyFormat format = PlyFormat::kAscii;
	std::vector<PlyElement> elements;
	size_t bodyOffset = 0; // first byte after "end_header\n"
	int bodyLine = 1; // line number of the first body line (ASCII)
};

bool parseType(std::string_view s, PlyType &type)
{
	struct Name {
		std::string_view name;
		PlyType type;
	};
	static constexpr Name kNames[] = {
		{"char", PlyType::kInt8}, {"int8", PlyType::kInt8},
		{"uchar", PlyType::kUint8}, {"uint8", PlyType::kUint8},
		{"short", PlyType::kInt16}, {"int16", PlyType::kInt16},
		{"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},
		{"int", PlyType::kInt32}, {"int32", PlyType::kInt32},
		{"uint", PlyType::kUint32}, {"uint32", PlyType::kUint32},
		{"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32},
		{"double", PlyType::kFloat64}, {"float64", PlyType::kFloat64},
	};
	for (const Name &n : kNames) {
		if (n.name == s) {
			type = n.type;
			return true;
		}
	}
	return false;
}

size_t typeSize(PlyType type)
{
	switch (type) {
	case PlyType::kInt8:
	case PlyType::kUint8:
		return 1;
	case PlyType::kInt16:
	case PlyType::kUint16:
		return 2;
	case PlyType::kInt32:
	case PlyType::kUint32:
	case PlyType::kFloat32:
		return 4;
	case PlyType::kFloat64:
		return 8;
	}
	return 0;
}

bool isIntegerType(PlyType type)
{
	return type != PlyType::kFloat32 && type != PlyType::kFloat64;
}

std::vector<std::string_view> splitWords(std::string_view line)
{
	std::vector<std::string_view> words;
	size_t i = 0;
	while (i < line.size()) {
		while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
			++i;
		size_t start = i;
		while (i < line.size() && line[i] != ' ' && line[i] != '\t')
			++i;
		if (i > start)
			words.push_back(line.substr(start, i - start));
	}
	return words;
}

class Loader
{
public:
	Loader(const std::filesystem::path &path, std::string data)
		: path_(path.string()), data_(std::move(data)) {}

	Expected<Mesh> load();

private:
	Error fail(Errc code, const std::string &what) const
	{
		return makeError(code, path_ + ": " + what);
	}

	Status parseHeader();
	Status addVertex(const std::vector<double> &values, size_t item, int lineNo);
	Status locateMeshProperties();
	Status readAscii();
	Status readBinary();
	Status checkFaces();

	std::string path_;
	std::string data_;
	PlyHeader header_;
	Mesh mesh_;

	// Indices into header_.elements / properties of what we keep.
	int vertexElement_ = -1;
	int faceElement_ = -1;
	int propX_ = -1, propY_ = -1, propZ_ = -1;
	int propNx_ = -1, propNy_ = -1, propNz_ = -1;
	int propIndices_ = -1;
};

Status Loader::parseHeader()
{
	std::string_view all(data_);
	size_t pos = 0;
	int lineNo = 0;
	bool sawFormat = false;

	bool terminated = false; // the last line read ends with a line break
	auto nextLine = [&](std::string_view &line) {
		if (pos >= all.size())
			return false;
		size_t eol = all.find('\n', pos);
		terminated = eol != std::string_view::npos;
		if (!terminated)
			eol = all.size();
		line = all.substr(pos, eol - pos);
		if (!line.empty() && line.back() == '\r')
			line.remove_suffix(1);
		pos = terminated ? eol + 1 : eol;
		++lineNo;
		return true;
	};

	std::string_view line;
	if (!nextLine(line) || line != "ply")
		return fail(Errc::kParse, "line 1: not a PLY file (missing 'ply' magic)");

	while (true) {
		if (!nextLine(line))
			return fail(Errc::kParse, "header has no 'end_header' line");
		std::vector<std::string_view> w = splitWords(line);
		std::string where = "header line " + std::to_string(lineNo) + ": ";
		if (w.empty() || w[0] == "comment" || w[0] == "obj_info")
			continue;
		if (w[0] == "end_header") {
			// The body starts after its line break; without one the
			// file was cut inside the header.
			if (!terminated)
				return fail(Errc::kCorrupt, where + "'end_header' has no line break (file truncated?)");
			break;
		}
		if (w[0] == "format") {
			if (w.size() != 3)
				return fail(Errc::kParse, where + "malformed 'format' line");
			if (w[1] == "ascii")
				header_.format = PlyFormat::kAscii;
			else if (w[1] == "binary_little_endian")
				header_.format = PlyFormat::kBinaryLittleEndian;
			else if (w[1] == "binary_big_endian")
				header_.format = PlyFormat::kBinaryBigEndian;
			else
				return fail(Errc::kUnsupported, where + "unknown format '" + std::string(w[1]) + "'");
			if (w[2] != "1.0")
				return fail(Errc::kUnsupported, where + "unsupported version '" + std::string(w[2]) + "'");
			sawFormat = true;
		} else if (w[0] == "element") {
			if (w.size() != 3)
				return fail(Errc::kParse, where + "malformed 'element' line");
			PlyElement el;
			el.name = std::string(w[1]);
			unsigned long long count = 0;
			auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
			if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size())
				return fail(Errc::kParse, where + "element '" + el.name + "' has a bad count '" + std::string(w[2]) + "'");
			el.count = count;
			header_.elements.push_back(std::move(el));
		} else if (w[0] == "property") {
			if (header_.elements.empty())
				return fail(Errc::kParse, where + "property before any element");
			PlyProperty prop;
			if (w.size() == 5 && w[1] == "list") {
				prop.isList = true;
				if (!parseType(w[2], prop.countType) || !parseType(w[3], prop.type))
					return fail(Errc::kParse, where + "unknown type in list property '" + std::string(w[4]) + "'");
				if (!isIntegerType(prop.countType))
					return fail(Errc::kParse, where + "list property '" + std::string(w[4]) + "' has a non-integer count type");
				prop.name = std::string(w[4]);
			} else if (w.size() == 3) {
				if (!parseType(w[1], prop.type))
					return fail(Errc::kParse, where + "unknown type '" + std::string(w[1]) + "' of property '" + std::string(w[2]) + "'");
				prop.name = std::string(w[2]);
			} else {
				return fail(Errc::kParse, where + "malformed 'property' line");
			}
			header_.elements.back().properties.push_back(std::move(prop));
		} else {
			return fail(Errc::kParse, where + "unknown keyword '" + std::string(w[0]) + "'");
		}
	}
	if (!sawFormat)
		return fail(Errc::kParse, "header has no 'format' line");
	header_.bodyOffset = pos;
	header_.bodyLine = lineNo + 1;
	return {};
}

Status Loader::locateMeshProperties()
{
	for (size_t e = 0; e < header_.elements.size(); ++e) {
		const PlyElement &el = header_.elements[e];
		if (el.name == "vertex" && vertexElement_ < 0)
			vertexElement_ = static_cast<int>(e);
		else if (el.name == "face" && faceElement_ < 0)
			faceElement_ = static_cast<int>(e);
	}
	if (vertexElement_ < 0)
		return fail(Errc::kParse, "header declares no 'vertex' element");

	const PlyElement &v = header_.elements[vertexElement_];
	if (v.count > std::numeric_limits<uint32_t>::max())
		return fail(Errc::kUnsupported, "element 'vertex': too many vertices (" + std::to_string(v.count) + ")");
	for (size_t p = 0; p < v.properties.size(); ++p) {
		const PlyProperty &prop = v.properties[p];
		int *slot = nullptr;
		if (prop.name == "x")
			slot = &propX_;
		else if (prop.name == "y")
			slot = &propY_;
		else if (prop.name == "z")
			slot = &propZ_;
		else if (prop.name == "nx")
			slot = &propNx_;
		else if (prop.name == "ny")
			slot = &propNy_;
		else if (prop.name == "nz")
			slot = &propNz_;
		if (!slot)
			continue;
		if (prop.isList)
			return fail(Errc::kParse, "element 'vertex' property '" + prop.name + "' must be a scalar, not a list");
		*slot = static_cast<int>(p);
	}
	if (propX_ < 0 || propY_ < 0 || propZ_ < 0)
		return fail(Errc::kParse, "element 'vertex' lacks one of the properties x, y, z");
	int normalCount = (propNx_ >= 0) + (propNy_ >= 0) + (propNz_ >= 0);
	if (normalCount != 0 && normalCount != 3)
		return fail(Errc::kParse, "element 'vertex' has some but not all of nx, ny, nz");

	if (faceElement_ >= 0) {
		const PlyElement &f = header_.elements[faceElement_];
		for (size_t p = 0; p < f.properties.size(); ++p) {
			const PlyProperty &prop = f.properties[p];
			if (prop.name == "vertex_indices" || prop.name == "vertex_index") {
				if (!prop.isList || !isIntegerType(prop.type))
					return fail(Errc::kParse, "element 'face' property '" + prop.name + "' must be a list of integers");
				propIndices_ = static_cast<int>(p);
				break;
			}
		}
		if (propIndices_ < 0)
			return fail(Errc::kParse, "element 'face' has no 'vertex_indices' list");
	}
	return {};
}

// Keeps position (and normal) of one vertex item; non-finite values are an
// error naming the property (and the line, for ASCII: lineNo > 0).
Status Loader::addVertex(const std::vector<double> &values, size_t item, int lineNo)
{
	const PlyElement &el = header_.elements[vertexElement_];
	const int props[6] = {propX_, propY_, propZ_, propNx_, propNy_, propNz_};
	const int used = propNx_ >= 0 ? 6 : 3;
	float f[6];
	for (int k = 0; k < used; ++k) {
		f[k] = static_cast<float>(values[props[k]]);
		if (!std::isfinite(f[k]))
			return fail(Errc::kCorrupt, (lineNo > 0 ? "line " + std::to_string(lineNo) + ": " : std::string()) +
							    "element 'vertex' item " + std::to_string(item) + " property '" +
							    el.properties[props[k]].name + "': non-finite value");
	}
	mesh_.vertices.emplace_back(f[0], f[1], f[2]);
	if (used == 6)
		mesh_.normals.emplace_back(f[3], f[4], f[5]);
	return {};
}

// Adds one polygon, fan-triangulated. Indices are range-checked later.
template<typename Index>
void addPolygon(Mesh &mesh, const Index *idx, size_t n)
{
	for (size_t k = 1; k + 1 < n; ++k)
		mesh.faces.push_back({static_cast<uint32_t>(idx[0]), static_cast<uint32_t>(idx[k]),
				      static_cast<uint32_t>(idx[k + 1])});
}

Status Loader::readAscii()
{
	const char *next = data_.data() + header_.bodyOffset;
	const char *end = data_.data() + data_.size();
	const char *p = next;
	const char *lineEnd = next;
	int lineNo = header_.bodyLine - 1;
	bool unterminated = false;

	// Moves to the next non-blank line; false at end of file.
	auto nextLine = [&]() {
		while (next < end) {
			p = next;
			++lineNo;
			const char *e = static_cast<const char *>(std::memchr(p, '\n', end - p));
			unterminated = !e;
			lineEnd = e ? e : end;
			next = e ? e + 1 : end;
			for (const char *q = p; q < lineEnd; ++q) {
				if (*q != ' ' && *q != '\t' && *q != '\r')
					return true;
			}
		}
		return false;
	};
	auto skipSpace = [&]() {
		while (p < lineEnd && (*p == ' ' || *p == '\t' || *p == '\r'))
			++p;
	};
	// Parses the next token as a number; integer types must be integers.
	auto number = [&](PlyType type, double &out) {
		skipSpace();
		if (p >= lineEnd)
			return false;
		const char *tokEnd = p;
		while (tokEnd < lineEnd && *tokEnd != ' ' && *tokEnd != '\t' && *tokEnd != '\r')
			++tokEnd;
		std::from_chars_result r;
		if (isIntegerType(type)) {
			long long v = 0;
			r = std::from_chars(p, tokEnd, v);
			out = static_cast<double>(v);
		} else if (type == PlyType::kFloat32) {
			// Parse as float so ASCII and binary files of one mesh agree bit for bit.
			float v = 0;
			r = std::from_chars(p, tokEnd, v);
			out = v;
		} else {
			r = std::from_chars(p, tokEnd, out);
		}
		if (r.ec != std::errc() || r.ptr != tokEnd)
			return false;
		p = tokEnd;
		return true;
	};

	std::vector<double> values;
	std::vector<int64_t> indices;
	for (size_t e = 0; e < header_.elements.size(); ++e) {
		const PlyElement &el = header_.elements[e];
		const bool isVertex = static_cast<int>(e) == vertexElement_;
		const bool isFace = static_cast<int>(e) == faceElement_;
		values.assign(el.properties.size(), 0.0);
		for (size_t i = 0; i < el.count; ++i) {
			if (!nextLine())
				return fail(Errc::kCorrupt, "truncated data: file ends in element '" + el.name + "' after " +
								    std::to_string(i) + " of " + std::to_string(el.count) + " items");
			// A file cut inside a line would otherwise parse as a shorter number.
			if (unterminated)
				return fail(Errc::kCorrupt, "line " + std::to_string(lineNo) + ": element '" + el.name +
								    "': truncated data (last line has no line break)");
			// Built only on error: this loop runs once per line.
			auto where = [&]() { return "line " + std::to_string(lineNo) + ": element '" + el.name + "' property '"; };
			for (size_t q = 0; q < el.properties.size(); ++q) {
				const PlyProperty &prop = el.properties[q];
				if (!prop.isList) {
					if (!number(prop.type, values[q]))
						return fail(Errc::kParse, where() + prop.name + "': missing or bad number");
					continue;
				}
				double countValue;
				if (!number(prop.countType, countValue) || countValue < 0)
					return fail(Errc::kParse, where() + prop.name + "': missing or bad list count");
				size_t count = static_cast<size_t>(countValue);
				// Each item takes at least two characters: refuse absurd
				// counts before allocating for them.
				if (count > static_cast<size_t>(lineEnd - p) / 2 + 1)
					return fail(Errc::kParse, where() + prop.name + "': list has fewer than " +
									  std::to_string(count) + " items");
				const bool keep = isFace && static_cast<int>(q) == propIndices_;
				if (keep)
					indices.resize(count);
				for (size_t k = 0; k < count; ++k) {
					double item;
					if (!number(prop.type, item))
						return fail(Errc::kParse, where() + prop.name + "': list has fewer than " +
										  std::to_string(count) + " items");
					if (keep)
						indices[k] = static_cast<int64_t>(item);
				}
				if (keep) {
					if (count < 3)
						return fail(Errc::kCorrupt, where() + prop.name + "': face with " +
										    std::to_string(count) + " indices (need at least 3)");
					for (size_t k = 0; k < count; ++k) {
						if (indices[k] < 0 || static_cast<uint64_t>(indices[k]) >= header_.elements[vertexElement_].count)
							return fail(Errc::kOutOfRange, where() + prop.name + "': vertex index " +
											       std::to_string(indices[k]) + " out of range [0, " +
											       std::to_string(header_.elements[vertexElement_].count) + ")");
					}
					addPolygon(mesh_, indices.data(), count);
				}
			}
			skipSpace();
			if (p < lineEnd)
				return fail(Errc::kParse, "line " + std::to_string(lineNo) + ": element '" + el.name +
								  "': more values than the header declares");
			if (isVertex) {
				if (Status s = addVertex(values, i, lineNo); !s)
					return s;
			}
		}
	}
	if (nextLine())
		return fail(Errc::kParse, "line " + std::to_string(lineNo) + ": data after the last declared element");
	return {};
}

// Sequential binary reader with bounds and byte-order handling.
class BinaryCursor
{
public:
	BinaryCursor(const char *p, const char *end, bool swap) : p_(p), end_(end), swap_(swap) {}

	bool read(PlyType type, double &out)
	{
		switch (type) {
		case PlyType::kInt8: return get<int8_t>(out);
		case PlyType::kUint8: return get<uint8_t>(out);
		case PlyType::kInt16: return get<int16_t>(out);
		case PlyType::kUint16: return get<uint16_t>(out);
		case PlyType::kInt32: return get<int32_t>(out);
		case PlyType::kUint32: return get<uint32_t>(out);
		case PlyType::kFloat32: return get<float>(out);
		case PlyType::kFloat64: return get<double>(out);
		}
		return false;
	}

	bool skip(size_t bytes)
	{
		if (static_cast<size_t>(end_ - p_) < bytes)
			return false;
		p_ += bytes;
		return true;
	}

	size_t remaining() const { return end_ - p_; }

private:
	template<typename T>
	bool get(double &out)
	{
		if (static_cast<size_t>(end_ - p_) < sizeof(T))
			return false;
		unsigned char bytes[sizeof(T)];
		std::memcpy(bytes, p_, sizeof(T));
		if (swap_) {
			for (size_t i = 0; i < sizeof(T) / 2; ++i)
				std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
		}
		T v;
		std::memcpy(&v, bytes, sizeof(T));
		out = static_cast<double>(v);
		p_ += sizeof(T);
		return true;
	}

	const char *p_;
	const char *end_;
	bool swap_;
};

Status Loader::readBinary()
{
	const bool fileLittle = header_.format == PlyFormat::kBinaryLittleEndian;
	const bool hostLittle = std::endian::native == std::endian::little;
	BinaryCursor in(data_.data() + header_.bodyOffset, data_.data() + data_.size(), fileLittle != hostLittle);

	std::vector<double> values;
	std::vector<int64_t> indices;
	for (size_t e = 0; e < header_.elements.size(); ++e) {
		const PlyElement &el = header_.elements[e];
		const bool isVertex = static_cast<int>(e) == vertexElement_;
		const bool isFace = static_cast<int>(e) == faceElement_;
		// An element without properties takes no bytes, whatever its count.
		if (el.properties.empty())
			continue;
		values.assign(el.properties.size(), 0.0);
		for (size_t i = 0; i < el.count; ++i) {
			auto truncated = [&](const PlyProperty &prop) {
				return fail(Errc::kCorrupt, "truncated data: file ends in element '" + el.name + "' item " +
								    std::to_string(i) + " of " + std::to_string(el.count) +
								    ", property '" + prop.name + "'");
			};
			for (size_t q = 0; q < el.properties.size(); ++q) {
				const PlyProperty &prop = el.properties[q];
				if (!prop.isList) {
					if (!in.read(prop.type, values[q]))
						return truncated(prop);
					continue;
				}
				double countValue;
				if (!in.read(prop.countType, countValue))
					return truncated(prop);
				if (countValue < 0)
					return fail(Errc::kCorrupt, "element '" + el.name + "' item " + std::to_string(i) +
									    " property '" + prop.name + "': negative list count");
				size_t count = static_cast<size_t>(countValue);
				const bool keep = isFace && static_cast<int>(q) == propIndices_;
				if (!keep) {
					if (count > in.remaining() / typeSize(prop.type) || !in.skip(count * typeSize(prop.type)))
						return truncated(prop);
					continue;
				}
				if (count > in.remaining() / typeSize(prop.type))
					return truncated(prop);
				indices.resize(count);
				for (size_t k = 0; k < count; ++k) {
					double item = 0; // always read: size checked above
					in.read(prop.type, item);
					indices[k] = static_cast<int64_t>(item);
				}
				if (count < 3)
					return fail(Errc::kCorrupt, "element 'face' item " + std::to_string(i) + " property '" +
									    prop.name + "': face with " + std::to_string(count) +
									    " indices (need at least 3)");
				for (size_t k = 0; k < count; ++k) {
					if (indices[k] < 0 || static_cast<uint64_t>(indices[k]) >=
								      header_.elements[vertexElement_].count)
						return fail(Errc::kOutOfRange, "element 'face' item " + std::to_string(i) +
										       " property '" + prop.name + "': vertex index " +
										       std::to_string(indices[k]) + " out of range [0, " +
										       std::to_string(header_.elements[vertexElement_].count) + ")");
				}
				addPolygon(mesh_, indices.data(), count);
			}
			if (isVertex) {
				if (Status s = addVertex(values, i, 0); !s)
					return s;
			}
		}
	}
	// Trailing bytes are tolerated (some writers pad the file).
	return {};
}

Expected<Mesh> Loader::load()
{
	if (Status s = parseHeader(); !s)
		return s.error();
	if (Status s = locateMeshProperties(); !s)
		return s.error();

	// Reserve no more than the remaining bytes could hold, so a lying
	// header cannot make us allocate gigabytes before noticing truncation.
	// parseHeader() leaves bodyOffset <= the file size.
	const size_t body = data_.size() - header_.bodyOffset;
	const size_t nv = header_.elements[vertexElement_].count;
	const size_t minVertexBytes = header_.format == PlyFormat::kAscii ? 6 : 12;
	if (nv > body / minVertexBytes + 1)
		return fail(Errc::kCorrupt, "truncated data: element 'vertex' declares " + std::to_string(nv) +
						    " items but the body has only " + std::to_string(body) + " bytes");
	mesh_.vertices.reserve(nv);
	if (propNx_ >= 0)
		mesh_.normals.reserve(nv);
	if (faceElement_ >= 0) {
		const size_t nf = header_.elements[faceElement_].count;
		mesh_.faces.reserve(std::min(nf, body / 4 + 1));
	}

	Status s = header_.format == PlyFormat::kAscii ? readAscii() : readBinary();
	if (!s)
		return s.error();
	return std::move(mesh_);
}

} // namespace

Expected<Mesh> loadPly(const std::filesystem::path &path)
{
	std::error_code ec;
	if (!std::filesystem::is_regular_file(path, ec))
		return makeError(Errc::kNotFound, path.string() + ": no such file");
	std::ifstream in(path, std::ios::binary);
	if (!in)
		return makeError(Errc::kIo, path.string() + ": cannot open for reading");
	std::ostringstream buf;
	buf << in.rdbuf();
	if (in.bad())
		return makeError(Errc::kIo, path.string() + ": read error");
	std::string data = std::move(buf).str();
	if (data.empty())
		return makeError(Errc::kParse, path.string() + ": empty file");
	return Loader(path, std::move(data)).load();
}

} // namespace ihf
