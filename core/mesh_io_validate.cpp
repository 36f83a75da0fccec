#include "core/mesh_io_validate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
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
  if (binary == "BINARY") {
    // Counts follow the keyword line as three 32-bit big-endian integers.
    if (text.size() < pos + 12) throw Error(path + ": binary OFF ends before its counts");
    auto be32 = [&](std::size_t at) {
      return std::uint32_t(std::uint8_t(text[at])) << 24 | std::uint32_t(std::uint8_t(text[at + 1])) << 16 |
             std::uint32_t(std::uint8_t(text[at + 2])) << 8 | std::uint32_t(std::uint8_t(text[at + 3]));
    };
    checkCounts(path, text.size(), be32(pos), be32(pos + 4), 12, 16);
    return text;
  }
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

std::string validatedPly(const std::string& path, const std::string& text) {
  static const std::set<std::string> kTypes = {"char",  "uchar", "short",  "ushort", "int",    "uint",
                                               "float", "double", "int8", "uint8",  "int16",  "uint16",
                                               "int32", "uint32", "float32", "float64"};
  std::size_t pos = 0;
  int number = 0;
  bool binary = false, sawFormat = false, ended = false, sawElement = false;
  std::uint64_t vertices = 0, faces = 0;
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
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") || w[2] != "1.0")
        fail(path, number, "unknown PLY format \"" + line + "\"");
      binary = w[1] != "ascii";
      sawFormat = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail(path, number, "PLY element line is not \"element NAME COUNT\"");
      const long long count = wholeNumber(path, number, w[2]);
      if (count < 0 || std::uint64_t(count) > kMaxElements) fail(path, number, "PLY element count " + w[2] + " out of range");
      if (w[1] == "vertex") vertices = std::uint64_t(count);
      if (w[1] == "face") faces = std::uint64_t(count);
      sawElement = true;
    } else if (w[0] == "property") {
      if (!sawElement) fail(path, number, "PLY property before any element");
      const bool list = w.size() == 5 && w[1] == "list" && kTypes.count(w[2]) && kTypes.count(w[3]);
      const bool scalar = w.size() == 3 && kTypes.count(w[1]);
      if (!list && !scalar) fail(path, number, "PLY property line \"" + line + "\" is not \"property TYPE NAME\" or a list");
    } else if (w[0] == "end_header" && w.size() == 1) {
      ended = true;
    } else {
      fail(path, number, "unknown PLY header line \"" + line + "\"");
    }
  }
  if (!sawFormat) throw Error(path + ": PLY header has no format line");
  checkCounts(path, text.size(), vertices, faces, binary ? 12 : 6, binary ? 13 : 8);
  if (!binary)
    for (const Line& l : tokenize(path, text, pos, number + 1))
      for (const std::string& t : l.tokens) finiteNumber(path, l.number, t);
  return text;
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
