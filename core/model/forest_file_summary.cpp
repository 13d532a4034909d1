// SPDX-License-Identifier: MIT
// formatForestFileSummary(): the text `ihf forest info` prints.

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>

#include "core/model/forest_file.h"

namespace ihf {

namespace {

void appendf(std::string &out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

void appendf(std::string &out, const char *fmt, ...)
{
	char buf[512];
	va_list ap;
	va_start(ap, fmt);
	int n = std::vsnprintf(buf, sizeof(buf), fmt, ap);
	va_end(ap);
	if (n > 0)
		out.append(buf, std::min<size_t>(static_cast<size_t>(n), sizeof(buf) - 1));
}

const char *encodingName(TemplateEncoding e)
{
	return e == TemplateEncoding::kFloat32 ? "float32" : "uint8 sparse";
}

} // namespace

std::string formatForestFileSummary(const ForestFileSummary &s)
{
	std::string out;
	appendf(out, "file: %s\n", s.path.c_str());
	appendf(out, "format version %u, %llu bytes, header CRC32 0x%08x, table CRC32 0x%08x\n",
		s.version, static_cast<unsigned long long>(s.fileSize), s.headerCrc, s.tableCrc);

	appendf(out, "sections: %zu\n", s.sections.size());
	appendf(out, "  %-16s %4s %10s %12s %8s %10s %10s\n", "type", "tree", "offset", "bytes",
		"element", "count", "crc32");
	for (const ForestFileSection &sec : s.sections) {
		const bool perTree = sec.type == SectionType::kNodes ||
				     sec.type == SectionType::kTemplates ||
				     sec.type == SectionType::kTemplateOffsets ||
				     sec.type == SectionType::kVotes;
		appendf(out, "  %-16s %4s %10llu %12llu %8u %10u 0x%08x\n", sectionTypeName(sec.type),
			perTree ? std::to_string(sec.tree).c_str() : "-",
			static_cast<unsigned long long>(sec.offset),
			static_cast<unsigned long long>(sec.size), sec.elementSize, sec.elementCount,
			sec.crc);
	}

	// Bytes by part of the model: what a smaller file would have to shrink.
	struct Part {
		const char *name;
		unsigned long long bytes = 0;
	};
	Part parts[] = {{"mesh"}, {"nodes"}, {"templates"}, {"votes"}, {"params"}, {"layout"}};
	unsigned long long sectionBytes = 0;
	for (const ForestFileSection &sec : s.sections) {
		size_t k = 4;
		switch (sec.type) {
		case SectionType::kMeshVertices:
		case SectionType::kMeshFaces:
		case SectionType::kMeshNormals: k = 0; break;
		case SectionType::kNodes: k = 1; break;
		case SectionType::kTemplates:
		case SectionType::kTemplateOffsets: k = 2; break;
		case SectionType::kVotes:
		case SectionType::kRotations: k = 3; break;
		default: break;
		}
		parts[k].bytes += sec.size;
		sectionBytes += sec.size;
	}
	parts[5].bytes = s.fileSize - std::min<unsigned long long>(s.fileSize, sectionBytes);
	out += "bytes by part:\n";
	for (const Part &p : parts)
		appendf(out, "  %-10s %12llu %5.1f %%\n", p.name, p.bytes,
			s.fileSize > 0 ? 100.0 * static_cast<double>(p.bytes) / static_cast<double>(s.fileSize)
				       : 0.0);
	out += "  (mesh: vertices, faces, normals; templates: with their offsets; votes: with the\n"
	       "  rotation table; params: PARAMS and FOREST; layout: header, section table, padding)\n";

	appendf(out, "forest: %zu trees, dims %d, templates %s, %u distinct vote rotations\n",
		s.trees.size(), s.dims, encodingName(s.encoding), s.rotations);
	appendf(out, "  %4s %10s %10s %10s %10s %6s %12s\n", "tree", "nodes", "leaves", "templates",
		"votes", "depth", "stored bins");
	unsigned long long nodes = 0, leaves = 0, templates = 0, votes = 0, bins = 0;
	int depth = 0;
	for (size_t t = 0; t < s.trees.size(); ++t) {
		const ForestTreeStats &ts = s.trees[t];
		appendf(out, "  %4zu %10u %10u %10u %10u %6d %12llu\n", t, ts.nodes, ts.leaves,
			ts.templates, ts.votes, ts.depth,
			static_cast<unsigned long long>(ts.templateBins));
		nodes += ts.nodes;
		leaves += ts.leaves;
		templates += ts.templates;
		votes += ts.votes;
		bins += ts.templateBins;
		depth = std::max(depth, ts.depth);
	}
	appendf(out, "  %4s %10llu %10llu %10llu %10llu %6d %12llu\n", "all", nodes, leaves, templates,
		votes, depth, bins);

	appendf(out, "mesh: %zu vertices, %zu faces, %s\n", s.vertices, s.faces,
		s.normals ? "with normals" : "no normals");
	if (s.nearSymmetries.empty()) {
		out += "near-symmetries: none stored\n";
	} else {
		appendf(out, "near-symmetries: %zu (turns that change only this share of the pixels of a view)\n",
			s.nearSymmetries.size());
		for (const NearSymmetry &ns : s.nearSymmetries) {
			char turn[32];
			if (ns.continuous())
				std::snprintf(turn, sizeof(turn), "any turn");
			else
				std::snprintf(turn, sizeof(turn), "turn %.0f deg", static_cast<double>(ns.turnDeg));
			appendf(out, "  axis (%.3f, %.3f, %.3f) through (%.1f, %.1f, %.1f) mm, %s, differing %.1f %%\n",
				static_cast<double>(ns.axis.x()), static_cast<double>(ns.axis.y()),
				static_cast<double>(ns.axis.z()), static_cast<double>(ns.point.x()),
				static_cast<double>(ns.point.y()), static_cast<double>(ns.point.z()), turn,
				100.0 * static_cast<double>(ns.differingShare));
		}
	}
	out += "params:\n";
	out += s.paramsJson;
	if (!s.paramsJson.empty() && s.paramsJson.back() != '\n')
		out += '\n';
	return out;
}

} // namespace ihf
