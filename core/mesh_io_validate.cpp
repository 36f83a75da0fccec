#include "core/mesh_io_validate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cerrno>
#include <cstdlib>
#include <set>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/gz_file.h"

namespace isoatlas {
namespace {

constexpr std::uint64_t kMaxElements = std::uint64_t(1) << 31;

struct Line {
  int number;  // 1-based, in the file
  std::vector<std::string> tokens;
};

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw Error(path + ": line " + std::to_string(line) + ": " + what);
}

// Splits ASCII text into lines of tokens, dropping '#' comments and blank lines.
std::vector<Line> tokenize(const std::string& path, const std::string& text, std::size_t from, int firstLine) {
  std::vector<Line> lines;
  int number = firstLine;
  std::size_t pos = from;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    for (unsigned char c : line)
      if (c < 0x20 && c != '\t' && c != '\r') fail(path, number, "control character in a text file");
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    Line l{number++, {}};
    for (std::string t; words >> t;) l.tokens.push_back(t);
    if (!l.tokens.empty()) lines.push_back(std::move(l));
  }
  return lines;
}

double finiteNumber(const std::string& path, int line, const std::string& token) {
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) fail(path, line, "\"" + token + "\" is not a finite number");
  return v;
}

long long wholeNumber(const std::string& path, int line, const std::string& token) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) fail(path, line, "\"" + token + "\" is not a whole number");
  return v;
}

void checkCounts(const std::string& path, std::size_t fileBytes, std::uint64_t vertices, std::uint64_t faces,
                 unsigned minVertexBytes, unsigned minFaceBytes) {
  if (vertices > kMaxElements || faces > kMaxElements || vertices * minVertexBytes + faces * minFaceBytes > fileBytes)
    throw Error(path + ": header announces " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
                " faces, more than the file's " + std::to_string(fileBytes) + " bytes can hold");
}

std::string join(const std::vector<Line>& lines) {
  std::string out;
  for (const Line& l : lines) {
    for (std::size_t i = 0; i < l.tokens.size(); ++i) out += (i ? " " : "") + l.tokens[i];
    out += '\n';
  }
  return out;
}

// --- OFF ---------------------------------------------------------------------------------------

std::string validatedOff(const std::string& path, const std::string& text) {
  // The keyword is the first token of the first line that is not blank or a comment.
  std::size_t pos = 0;
  int number = 0;
  std::string keywordLine;
  while (pos < text.size() && keywordLine.empty()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    keywordLine = text.substr(pos, end - pos);
    ++number;
    pos = end + 1;
    if (const auto hash = keywordLine.find('#'); hash != std::string::npos) keywordLine.resize(hash);
    if (keywordLine.find_first_not_of(" \t\r") == std::string::npos) keywordLine.clear();
  }
  std::istringstream head(keywordLine);
  std::string keyword;
  head >> keyword;
  static const std::set<std::string> kKeywords = {"OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCOFF", "STNOFF", "STCNOFF", "4OFF"};
  if (!kKeywords.count(keyword)) throw Error(path + ": not an OFF file (its first line is not OFF, COFF, NOFF, ...)");
  std::string binary;
  head >> binary;
  // OpenMesh 9 reads a binary OFF's numbers in the machine's order where the format says big-endian,
  // and loops on counts it failed to read (fuzzing found a hang): such files are refused.
  if (binary == "BINARY") throw Error(path + ": binary OFF is not read; save it as ASCII OFF, PLY or OBJ");
  // ASCII: counts (on the keyword line or the next), then one vertex per line, then one face per line.
  std::vector<Line> lines = tokenize(path, text, pos, number + 1);
  std::vector<std::string> rest;
  for (std::string t; head >> t;) rest.push_back(t);
  if (rest.empty() && !lines.empty()) {
    rest = lines.front().tokens;
    number = lines.front().number;
    lines.erase(lines.begin());
  }
  if (rest.size() < 2) throw Error(path + ": the OFF counts are not \"V F E\"");
  const long long v = wholeNumber(path, number, rest[0]), f = wholeNumber(path, number, rest[1]);
  if (v < 0 || f < 0) fail(path, number, "negative vertex or face count");
  checkCounts(path, text.size(), std::uint64_t(v), std::uint64_t(f), 6, 8);
  const std::size_t dims = keyword.find('4') != std::string::npos ? 4 : 3;
  if (lines.size() < std::size_t(v + f))
    throw Error(path + ": OFF has " + std::to_string(lines.size()) + " vertex and face lines, the header announces " +
                std::to_string(v + f) + " (isoatlas reads one vertex or face per line)");
  // A vertex line: coordinates, then a normal (N), texture coordinates (ST), a colour (C); anything
  // further is cut, as OpenMesh would misread it.
  const bool colour = keyword.find('C') != std::string::npos;
  const std::size_t expected = dims + (keyword.find('N') != std::string::npos ? 3 : 0) + (keyword.rfind("ST", 0) == 0 ? 2 : 0);
  for (long long i = 0; i < v; ++i) {
    Line& l = lines[std::size_t(i)];
    if (l.tokens.size() < expected) fail(path, l.number, "a vertex needs " + std::to_string(expected) + " numbers");
    for (const std::string& t : l.tokens) finiteNumber(path, l.number, t);
    if (!colour) l.tokens.resize(expected);
  }
  for (long long i = v; i < v + f; ++i) {
    Line& l = lines[std::size_t(i)];
    const long long corners = wholeNumber(path, l.number, l.tokens[0]);
    if (corners < 3 || std::size_t(corners) + 1 > l.tokens.size())
      fail(path, l.number, "a face of " + l.tokens[0] + " corners with " + std::to_string(l.tokens.size() - 1) +
                               " numbers (needs 3 or more corners, each a vertex index)");
    for (long long c = 1; c <= corners; ++c) {
      const long long id = wholeNumber(path, l.number, l.tokens[std::size_t(c)]);
      if (id < 0 || id >= v) fail(path, l.number, "vertex index " + std::to_string(id) + " is not below " + std::to_string(v));
    }
    for (std::size_t t = std::size_t(corners) + 1; t < l.tokens.size(); ++t) finiteNumber(path, l.number, l.tokens[t]);
    l.tokens.resize(std::size_t(corners) + 1);  // colours dropped: OpenMesh misreads them
  }
  lines.resize(std::size_t(v + f));
  Line counts{0, {std::to_string(v), std::to_string(f), "0"}};
  lines.insert(lines.begin(), counts);
  return keyword + "\n" + join(lines);
}

// --- PLY ---------------------------------------------------------------------------------------

struct PlyProperty {
  std::string name;
  int countBytes = 0;  // 0 for a scalar; else the list's count type size
  bool countInteger = true;
  int valueBytes = 4;
  bool valueInteger = false;
};
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool plyType(const std::string& t, int& bytes, bool& integer) {
  static const std::pair<const char*, int> kTypes[] = {
      {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
      {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
      {"double", 8}, {"float64", 8}};
  for (const auto& [name, size] : kTypes)
    if (t == name) {
      bytes = size;
      integer = t.find("float") == std::string::npos && t != "double";
      return true;
    }
  return false;
}

// Walks a binary PLY body element by element, so every list count is checked against the bytes left
// and every face corner against the vertex count.
void checkBinaryPlyBody(const std::string& path, const std::string& text, std::size_t pos,
                        const std::vector<PlyElement>& elements, bool bigEndian) {
  auto readInt = [&](int bytes, bool isSigned) -> long long {
    if (pos + std::size_t(bytes) > text.size()) throw Error(path + ": binary PLY body ends early");
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) {
      const std::uint8_t byte = std::uint8_t(text[pos + std::size_t(bigEndian ? i : bytes - 1 - i)]);
      v = (v << 8) | byte;
    }
    pos += std::size_t(bytes);
    if (isSigned && bytes < 8 && (v >> (8 * bytes - 1)) & 1) return (long long)v - (1LL << (8 * bytes));
    return (long long)v;
  };
  std::uint64_t vertices = 0;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    for (std::uint64_t n = 0; n < e.count; ++n)
      for (const PlyProperty& p : e.properties) {
        if (p.countBytes == 0) {
          if (pos + std::size_t(p.valueBytes) > text.size()) throw Error(path + ": binary PLY body ends early");
          pos += std::size_t(p.valueBytes);
          continue;
        }
        const long long count = readInt(p.countBytes, true);
        if (count < 0 || pos + std::size_t(count) * std::size_t(p.valueBytes) > text.size())
          throw Error(path + ": binary PLY list of " + std::to_string(count) + " values runs past the file's end");
        const bool corners = e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (corners && count < 3) throw Error(path + ": a face has " + std::to_string(count) + " corners (needs 3 or more)");
        for (long long i = 0; i < count; ++i) {
          if (corners && p.valueInteger) {
            const long long id = readInt(p.valueBytes, true);
            if (id < 0 || std::uint64_t(id) >= vertices)
              throw Error(path + ": face " + std::to_string(n) + " names vertex " + std::to_string(id) + " of " +
                          std::to_string(vertices));
          } else {
            pos += std::size_t(p.valueBytes);
          }
        }
      }
  }
}

// The same walk over an ASCII body's tokens.
void checkAsciiPlyBody(const std::string& path, const std::string& text, std::size_t pos, int firstLine,
                       const std::vector<PlyElement>& elements) {
  const std::vector<Line> lines = tokenize(path, text, pos, firstLine);
  std::size_t li = 0, ti = 0;
  auto next = [&]() -> std::pair<const std::string*, int> {
    while (li < lines.size() && ti >= lines[li].tokens.size()) ++li, ti = 0;
    if (li >= lines.size()) throw Error(path + ": PLY body ends before its last element");
    return {&lines[li].tokens[ti++], lines[li].number};
  };
  std::uint64_t vertices = 0;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    for (std::uint64_t n = 0; n < e.count; ++n)
      for (const PlyProperty& p : e.properties) {
        long long count = 1;
        if (p.countBytes) {
          const auto [token, line] = next();
          count = wholeNumber(path, line, *token);
          if (count < 0 || count > (1 << 20)) fail(path, line, "a PLY list of " + *token + " values");
        }
        const bool corners = e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (corners && count < 3) throw Error(path + ": a face has " + std::to_string(count) + " corners (needs 3 or more)");
        for (long long i = 0; i < count; ++i) {
          const auto [token, line] = next();
          if (corners) {
            const long long id = wholeNumber(path, line, *token);
            if (id < 0 || std::uint64_t(id) >= vertices)
              fail(path, line, "vertex index " + *token + " is not below " + std::to_string(vertices));
          } else if (p.valueInteger) {
            wholeNumber(path, line, *token);
          } else {
            finiteNumber(path, line, *token);
          }
        }
      }
  }
}

// The text without its header's obj_info lines (the header ends at bodyStart). OpenMesh 9's PLY
// reader reads an obj_info line's words as header keywords, and looped forever on some (found by
// fuzzing); they say nothing we use.
std::string withoutObjInfoLines(const std::string& text, std::size_t bodyStart) {
  std::string out;
  for (std::size_t pos = 0; pos < bodyStart;) {
    const std::size_t newline = text.find('\n', pos);
    const std::size_t end = newline == std::string::npos ? bodyStart : std::min(newline + 1, bodyStart);
    const std::string line = text.substr(pos, end - pos);
    std::string firstWord;  // as validatedPly splits a line
    std::istringstream(line) >> firstWord;
    if (firstWord != "obj_info") out += line;
    pos = end;
  }
  return out.append(text, bodyStart, std::string::npos);
}

std::string validatedPly(const std::string& path, const std::string& text) {
  std::size_t pos = 0;
  int number = 0;
  std::string format;
  bool ended = false;
  std::vector<PlyElement> elements;
  bool objInfo = false;
  while (!ended) {
    if (pos >= text.size()) throw Error(path + ": PLY header has no end_header");
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++number;
    if (number > 10000) throw Error(path + ": PLY header is longer than 10000 lines");
    for (unsigned char c : line)
      if (c < 0x20 && c != '\t' && c != '\r') fail(path, number, "control character in the PLY header");
    std::istringstream in(line);
    std::vector<std::string> w;
    for (std::string t; in >> t;) w.push_back(t);
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") throw Error(path + ": not a PLY file (it does not start with \"ply\")");
      continue;
    }
    if (w.empty() || w[0] == "comment") continue;
    if (w[0] == "obj_info") {
      objInfo = true;
      continue;
    }
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") || w[2] != "1.0")
        fail(path, number, "unknown PLY format \"" + line + "\"");
      format = w[1];
    } else if (w[0] == "element") {
      if (w.size() != 3) fail(path, number, "PLY element line is not \"element NAME COUNT\"");
      const long long count = wholeNumber(path, number, w[2]);
      if (count < 0 || std::uint64_t(count) > kMaxElements) fail(path, number, "PLY element count " + w[2] + " out of range");
      elements.push_back({w[1], std::uint64_t(count), {}});
    } else if (w[0] == "property") {
      if (elements.empty()) fail(path, number, "PLY property before any element");
      PlyProperty p;
      bool ok = false;
      if (w.size() == 5 && w[1] == "list") {
        ok = plyType(w[2], p.countBytes, p.countInteger) && p.countInteger && plyType(w[3], p.valueBytes, p.valueInteger);
        p.name = w[4];
      } else if (w.size() == 3) {
        ok = plyType(w[1], p.valueBytes, p.valueInteger);
        p.name = w[2];
      }
      if (!ok) fail(path, number, "PLY property line \"" + line + "\" is not \"property TYPE NAME\" or an integer-counted list");
      elements.back().properties.push_back(p);
    } else if (w[0] == "end_header" && w.size() == 1) {
      ended = true;
    } else {
      fail(path, number, "unknown PLY header line \"" + line + "\"");
    }
  }
  if (format.empty()) throw Error(path + ": PLY header has no format line");
  std::uint64_t vertices = 0, faces = 0;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    if (e.name == "face") faces = e.count;
  }
  const bool binary = format != "ascii";
  checkCounts(path, text.size(), vertices, faces, binary ? 12 : 6, binary ? 13 : 8);
  if (binary) checkBinaryPlyBody(path, text, pos, elements, format == "binary_big_endian");
  else checkAsciiPlyBody(path, text, pos, number + 1, elements);
  return objInfo ? withoutObjInfoLines(text, std::min(pos, text.size())) : text;
}

// --- OBJ ---------------------------------------------------------------------------------------

std::string validatedObj(const std::string& path, const std::string& text) {
  std::vector<Line> lines = tokenize(path, text, 0, 1);
  std::vector<Line> kept;  // only v, vt, vn and f reach OpenMesh: mtllib would make it open other files
  long long v = 0, vt = 0, vn = 0;
  for (const Line& l : lines) {
    const std::string& k = l.tokens[0];
    if (k == "v" || k == "vn" || k == "vt") {
      const std::size_t need = k == "vt" ? 1 : 3;
      if (l.tokens.size() < need + 1) fail(path, l.number, "\"" + k + "\" needs " + std::to_string(need) + " numbers");
      for (std::size_t i = 1; i < l.tokens.size(); ++i) finiteNumber(path, l.number, l.tokens[i]);
      (k == "v" ? v : (k == "vt" ? vt : vn))++;
      kept.push_back(l);
    } else if (k == "f") {
      if (l.tokens.size() < 4) fail(path, l.number, "a face needs 3 or more corners");
      for (std::size_t i = 1; i < l.tokens.size(); ++i) {
        // v, v/t, v//n or v/t/n; negative indices count back from the last one read.
        std::istringstream parts(l.tokens[i]);
        std::string part;
        const long long counts[3] = {v, vt, vn};
        for (int slot = 0; std::getline(parts, part, '/'); ++slot) {
          if (slot > 2) fail(path, l.number, "face corner \"" + l.tokens[i] + "\" has more than three parts");
          if (part.empty() && slot > 0) continue;
          const long long id = wholeNumber(path, l.number, part);
          if (id == 0 || id > counts[slot] || -id > counts[slot])
            fail(path, l.number, "face corner \"" + l.tokens[i] + "\" refers past what was read so far");
        }
      }
      kept.push_back(l);
    }
    // Other statements (o, g, s, usemtl, mtllib, l, ...) carry nothing a Mesh keeps.
  }
  return join(kept);
}

}  // namespace

std::string validatedMeshText(const std::string& path, const std::string& text) {
  if (endsWith(path, ".off")) return validatedOff(path, text);
  if (endsWith(path, ".ply")) return validatedPly(path, text);
  if (endsWith(path, ".obj")) return validatedObj(path, text);
  return text;  // STL: binary by size, ASCII by keywords; OpenMesh's reader survived fuzzing
}

}  // namespace isoatlas
