#include "core/gl/shader_library.h"

#include <cstring>
#include <set>
#include <sstream>

#include "core/error.h"

namespace isoatlas::gl {
namespace {

const char* find(const EmbeddedShader* files, const std::string& path) {
  for (const EmbeddedShader* s = files; s->path; ++s)
    if (path == s->path) return s->source;
  return nullptr;
}

std::string expand(const EmbeddedShader* files, const std::string& path, std::set<std::string>& open) {
  const char* source = find(files, path);
  if (!source) throw Error("shader " + path + " is not embedded in this library", ErrorKind::Failure);
  if (!open.insert(path).second) throw Error("shader " + path + " includes itself", ErrorKind::Failure);
  const std::string folder = path.substr(0, path.rfind('/') + 1);
  std::istringstream in(source);
  std::ostringstream out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      const auto a = line.find('"'), b = line.rfind('"');
      if (a == std::string::npos || b <= a)
        throw Error(path + ":" + std::to_string(number) + ": malformed #include", ErrorKind::Failure);
      const std::string name = line.substr(a + 1, b - a - 1);
      const std::string target = find(files, folder + name) ? folder + name : name;
      out << expand(files, target, open) << "\n";
    } else {
      out << line << "\n";
    }
  }
  open.erase(path);
  return out.str();
}

}  // namespace

std::string shaderSource(const EmbeddedShader* files, const std::string& path) {
  std::set<std::string> open;
  return expand(files, path, open);
}

std::vector<EmbeddedShader> joinShaderTables(std::initializer_list<const EmbeddedShader*> tables) {
  std::vector<EmbeddedShader> joined;
  for (const EmbeddedShader* table : tables)
    for (const EmbeddedShader* s = table; s->path; ++s) joined.push_back(*s);
  joined.push_back({nullptr, nullptr});
  return joined;
}

}  // namespace isoatlas::gl
