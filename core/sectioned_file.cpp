#include "core/sectioned_file.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>

#include "core/atomic_file.h"

namespace isoatlas {
namespace {

std::uint32_t crc(const char* data, std::size_t size) {
  uLong c = crc32(0L, Z_NULL, 0);
  while (size > 0) {  // zlib takes 32-bit lengths
    const uInt n = uInt(std::min<std::size_t>(size, 1u << 30));
    c = crc32(c, reinterpret_cast<const Bytef*>(data), n);
    data += n, size -= n;
  }
  return std::uint32_t(c);
}

}  // namespace

SectionedFileWriter::SectionedFileWriter(const std::string& path, const char magic[8], std::uint32_t version)
    : path_(path), temporary_(temporaryPathFor(path)), out_(temporary_, std::ios::binary | std::ios::trunc) {
  if (!out_) throw Error(path + ": cannot open for writing");
  SectionWriter header;
  header.bytes.assign(magic, 8);
  header.put(version);
  out_.write(header.bytes.data(), std::streamsize(header.bytes.size()));
}

void SectionedFileWriter::section(const char tag[4], const SectionWriter& payload) {
  SectionWriter header;
  header.bytes.assign(tag, 4);
  header.put(std::uint64_t(payload.bytes.size()));
  header.put(crc(payload.bytes.data(), payload.bytes.size()));
  out_.write(header.bytes.data(), std::streamsize(header.bytes.size()));
  out_.write(payload.bytes.data(), std::streamsize(payload.bytes.size()));
}

SectionedFileWriter::~SectionedFileWriter() {
  if (finished_) return;
  out_.close();
  std::remove(temporary_.c_str());
}

void SectionedFileWriter::finish() {
  out_.close();
  if (!out_) throw Error(path_ + ": write failed (disk full?)", ErrorKind::Failure);
  finished_ = true;
  replaceWith(temporary_, path_);
}

SectionedFile readSectionedFile(const std::string& path, const char magic[8], const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open (missing or unreadable)");
  SectionedFile f;
  f.path = path;
  f.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (f.bytes.size() < 12 || std::memcmp(f.bytes.data(), magic, 8) != 0) throw Error(path + ": not " + what);
  f.version = SectionReader(path, f.bytes, "header", 8, 12).get<std::uint32_t>();
  return f;
}

void forEachSection(const SectionedFile& file, bool checksums,
                    const std::function<void(const std::string& tag, SectionReader& reader)>& read) {
  const std::string& bytes = file.bytes;
  std::size_t at = 12;
  while (at < bytes.size()) {
    if (bytes.size() - at < 16) throw Error(file.path + ": byte " + std::to_string(at) + ": truncated section header");
    const std::string tag = bytes.substr(at, 4);
    SectionReader header(file.path, bytes, tag, at + 4, at + 16);
    const std::uint64_t size = header.get<std::uint64_t>();
    const std::uint32_t sum = header.get<std::uint32_t>();
    at += 16;
    if (size > bytes.size() - at)
      throw Error(file.path + ": section " + tag + ", byte " + std::to_string(at) + ": runs past the end of the file (truncated?)");
    if (checksums && crc(bytes.data() + at, size) != sum)
      throw Error(file.path + ": section " + tag + ", byte " + std::to_string(at) + ": checksum mismatch (the file is damaged)");
    SectionReader r(file.path, bytes, tag, at, at + size);
    read(tag, r);
    at += size;
  }
}

}  // namespace isoatlas
