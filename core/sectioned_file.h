// The layout of the binary files isoatlas writes (.isoatlas models, .dvt trees): an 8-byte magic, a
// format version (u32), then sections until the end of the file, each: tag (4 ASCII bytes), payload
// length (u64), CRC-32 of the payload (u32, zlib's), payload. Little-endian on every machine: values
// are written and read byte by byte, never by casting structs.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>
#include <bit>

#include "core/error.h"
#include "core/vec.h"

namespace isoatlas {

// A section's payload as it is built.
class SectionWriter {
public:
  template <class T>
  void put(T value) {
    if constexpr (std::is_floating_point_v<T>) {
      using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
      put(std::bit_cast<Bits>(value));
    } else {
      using U = std::make_unsigned_t<T>;
      const U u = U(value);
      for (std::size_t i = 0; i < sizeof(T); ++i) bytes.push_back(char((u >> (8 * i)) & 0xff));
    }
  }
  void putVec(const Vec3& v) { put(v.x), put(v.y), put(v.z); }
  // Bytes as they are (SectionReader::take reads them back).
  void putBytes(const std::vector<std::uint8_t>& raw) { bytes.append(raw.begin(), raw.end()); }
  std::string bytes;
};

// Writes the magic and version, then section() appends sections, under a temporary name beside `path`
// (core/atomic_file.h); finish() puts the whole file at `path`. Destroyed unfinished (an error while
// writing), it removes the temporary and leaves `path` as it was.
class SectionedFileWriter {
public:
  SectionedFileWriter(const std::string& path, const char magic[8], std::uint32_t version);
  ~SectionedFileWriter();
  SectionedFileWriter(const SectionedFileWriter&) = delete;
  SectionedFileWriter& operator=(const SectionedFileWriter&) = delete;
  void section(const char tag[4], const SectionWriter& payload);
  void finish();  // flushes and renames; throws Error (Failure) when the data did not reach the file

private:
  std::string path_, temporary_;
  std::ofstream out_;
  bool finished_ = false;
};

// Reads one section's payload; every failure throws Error naming the file, the section and the byte.
class SectionReader {
public:
  SectionReader(const std::string& path, const std::string& bytes, std::string section, std::size_t begin, std::size_t end)
      : path_(path), bytes_(bytes), section_(std::move(section)), at_(begin), end_(end) {}
  template <class T>
  T get() {
    need(sizeof(T));
    if constexpr (std::is_floating_point_v<T>) {
      using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
      return std::bit_cast<T>(get<Bits>());
    } else {
      using U = std::make_unsigned_t<T>;
      U u = 0;
      for (std::size_t i = 0; i < sizeof(T); ++i) u = U(u | (U(std::uint8_t(bytes_[at_ + i])) << (8 * i)));
      at_ += sizeof(T);
      return T(u);
    }
  }
  // A count (u64) of items of `itemBytes` each that must fit in what is left of the section.
  std::uint64_t count(std::size_t itemBytes, const char* what) {
    const std::uint64_t n = get<std::uint64_t>();
    fits(n, itemBytes, what);
    return n;
  }
  void fits(std::uint64_t n, std::size_t itemBytes, const char* what) const {
    if (n > (end_ - at_) / itemBytes) fail(std::string(what) + " count " + std::to_string(n) + " exceeds the section");
  }
  template <class T>
  T finite() {
    const T v = get<T>();
    if (!std::isfinite(v)) fail("a real number is not finite");
    return v;
  }
  Vec3 vec() {
    Vec3 v;
    v.x = finite<double>(), v.y = finite<double>(), v.z = finite<double>();
    return v;
  }
  std::uint32_t index(std::uint64_t limit, const char* what) {
    const std::uint32_t i = get<std::uint32_t>();
    if (i >= limit) fail(std::string(what) + " index " + std::to_string(i) + " out of range");
    return i;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(path_ + ": section " + section_ + ", byte " + std::to_string(at_) + ": " + why);
  }
  void need(std::size_t n) const {
    if (n > end_ - at_) fail("the section ends early");
  }
  bool done() const { return at_ == end_; }
  std::size_t left() const { return end_ - at_; }
  const std::string& path() const { return path_; }
  // The next n bytes as they are (valid while the file's bytes are).
  const std::uint8_t* take(std::size_t n) {
    need(n);
    const auto* at = reinterpret_cast<const std::uint8_t*>(bytes_.data() + at_);
    at_ += n;
    return at;
  }

private:
  const std::string& path_;
  const std::string& bytes_;
  std::string section_;
  std::size_t at_, end_;
};

struct SectionedFile {
  std::string path, bytes;
  std::uint32_t version = 0;
};
// The whole file, its magic checked (`what` names the kind of file in the error); the caller checks
// the version.
SectionedFile readSectionedFile(const std::string& path, const char magic[8], const std::string& what);
// Calls `read` on each section in order, its length checked against the file and (with `checksums`)
// its CRC.
void forEachSection(const SectionedFile& file, bool checksums,
                    const std::function<void(const std::string& tag, SectionReader& reader)>& read);

}  // namespace isoatlas
