#include "core/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace isoatlas {

namespace {

// This machine's name, as temporaries carry it: a pid says nothing of a process on another host
// sharing the folder (a cohort's workers across hosts). '/' could not be in a file name.
const std::string& hostName() {
  static const std::string name = [] {
    char text[256] = {};
    if (::gethostname(text, sizeof text - 1) != 0 || !text[0]) return std::string("localhost");
    std::string host(text);
    std::replace(host.begin(), host.end(), '/', '_');
    return host;
  }();
  return name;
}

}  // namespace

std::string temporaryPathFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};  // unique per call: writes may run concurrently
  const std::filesystem::path p(path);
  std::string name(".");  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "." + string
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += '@';
  name += hostName();
  name += ".partial.";
  name += p.filename().string();
  return (p.parent_path() / name).string();
}

void replaceWith(const std::string& temporary, const std::string& path) {
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw Error(path + ": could not replace it with the finished file", ErrorKind::Failure);
  }
}

void requireOutputFolder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  require(folder.empty() || std::filesystem::is_directory(folder, ec), path + ": its folder does not exist");
}

namespace {

// Temporaries of `path` that a killed writer left beside it: ".<pid>-<n>@<host>.partial.<name>" of
// this host whose process is gone (a live one, ours or another's, may still be writing; another
// host's pid cannot be asked after, so its temporaries stay). Removed after a write of `path`
// succeeds; a folder that cannot be read is left alone.
void removeAbandonedTemporaries(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string suffix = ".partial." + p.filename().string();
  const std::filesystem::path folder = p.parent_path().empty() ? std::filesystem::path(".") : p.parent_path();
  std::error_code ec;
  for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= suffix.size() + 1 || name[0] != '.' || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    // "<pid>-<n>@<host>" between the dot and the suffix; anything else is not ours.
    const char* first = name.data() + 1;
    const char* last = name.data() + name.size() - suffix.size();
    pid_t pid = 0;
    const auto [dash, error] = std::from_chars(first, last, pid);
    if (error != std::errc() || pid <= 0 || dash == last || *dash != '-') continue;
    const char* at = std::find(dash, last, '@');
    if (at == last || std::string(at + 1, last) != hostName()) continue;
    if (::kill(pid, 0) != 0 && errno == ESRCH) std::filesystem::remove(it->path(), ec), ec.clear();
  }
}

}  // namespace

void writeAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write) {
  requireOutputFolder(path);
  const std::string temporary = temporaryPathFor(path);
  try {
    write(temporary);
  } catch (const Error& e) {
    std::remove(temporary.c_str());
    // The user named `path`, not our temporary: say that name.
    std::string message = e.what();
    for (std::size_t at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at + path.size()))
      message.replace(at, temporary.size(), path);
    throw Error(message, e.kind());
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  replaceWith(temporary, path);
  removeAbandonedTemporaries(path);
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  writeAtomically(path, [&](const std::string& to) {
    std::ofstream out(to, std::ios::binary);
    if (!out) throw Error(path + ": cannot open for writing");
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw Error(path + ": could not finish writing (disk full?)", ErrorKind::Failure);
  });
}

}  // namespace isoatlas
