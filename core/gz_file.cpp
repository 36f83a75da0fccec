#include "core/gz_file.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace isoatlas {

GzFile::GzFile(const std::string& path, const char* mode) : path_(path) {
  gz_ = gzopen(path.c_str(), mode);
  if (!gz_)
    throw Error(path + ": cannot open" + (mode[0] == 'r' ? " for reading: " : " for writing: ") +
                std::strerror(errno));
  gzbuffer(static_cast<gzFile>(gz_), 1 << 18);
}

GzFile::~GzFile() {
  if (gz_) gzclose(static_cast<gzFile>(gz_));
}

std::size_t GzFile::read(void* dst, std::size_t bytes) {
  std::size_t done = 0;
  while (done < bytes) {
    const unsigned chunk = unsigned(std::min<std::size_t>(bytes - done, 1u << 30));
    const int got = gzread(static_cast<gzFile>(gz_), static_cast<char*>(dst) + done, chunk);
    if (got < 0) {
      int code = 0;
      throw Error(path_ + ": read error: " + gzerror(static_cast<gzFile>(gz_), &code));
    }
    if (got == 0) break;
    done += std::size_t(got);
  }
  return done;
}

void GzFile::write(const void* src, std::size_t bytes) {
  std::size_t done = 0;
  while (done < bytes) {
    const unsigned chunk = unsigned(std::min<std::size_t>(bytes - done, 1u << 30));
    const int put = gzwrite(static_cast<gzFile>(gz_), static_cast<const char*>(src) + done, chunk);
    if (put <= 0) throw Error(path_ + ": write failed (disk full?)", ErrorKind::Failure);
    done += std::size_t(put);
  }
}

void GzFile::skip(std::uint64_t bytes) {
  char buf[4096];
  while (bytes > 0) {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(bytes, sizeof buf));
    if (read(buf, n) != n) throw Error(path_ + ": file ends inside its header");
    bytes -= n;
  }
}

void GzFile::close() {
  if (!gz_) return;
  const int rc = gzclose(static_cast<gzFile>(gz_));
  gz_ = nullptr;
  if (rc != Z_OK) throw Error(path_ + ": could not finish writing the file", ErrorKind::Failure);
}

std::vector<std::byte> GzFile::readExactly(std::uint64_t bytes, const std::string& where) {
  constexpr std::uint64_t kChunk = std::uint64_t(64) << 20;
  std::vector<std::byte> out;
  out.reserve(std::size_t(std::min(bytes, kChunk)));
  while (out.size() < bytes) {
    const std::size_t want = std::size_t(std::min<std::uint64_t>(bytes - out.size(), kChunk));
    const std::size_t at = out.size();
    out.resize(at + want);
    const std::size_t got = read(out.data() + at, want);
    if (got < want)
      throw Error(where + ": truncated: voxel data ends after " + std::to_string(at + got) + " of " +
                  std::to_string(bytes) + " bytes");
  }
  return out;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

void swapBytes(std::byte* data, std::size_t count, std::size_t size) {
  if (size < 2) return;
  for (std::size_t n = 0; n < count; ++n) std::reverse(data + n * size, data + (n + 1) * size);
}

}  // namespace isoatlas
