// GzFile: a file read or written through zlib, which passes plain (uncompressed) files through
// unchanged, so one reader serves .inr and .inr.gz, .nii and .nii.gz data alike.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace isoatlas {

class GzFile {
public:
  // mode "rb", or "wb" (compressed, level 6) / "wbT" (plain) as zlib's gzopen takes it.
  GzFile(const std::string& path, const char* mode);
  ~GzFile();
  GzFile(const GzFile&) = delete;
  GzFile& operator=(const GzFile&) = delete;

  std::size_t read(void* dst, std::size_t bytes);  // bytes read; fewer only at end of file
  void write(const void* src, std::size_t bytes);  // throws Error on failure
  void skip(std::uint64_t bytes);                  // throws Error when the file ends first
  void close();                                    // flushes; throws Error on failure

  // Reads `bytes` bytes in bounded chunks, so a header that claims more data than the file holds
  // fails on the short read instead of allocating everything first. Throws Error naming `where`.
  std::vector<std::byte> readExactly(std::uint64_t bytes, const std::string& where);

private:
  void* gz_ = nullptr;
  std::string path_;
};

bool endsWith(const std::string& s, const std::string& suffix);  // case-insensitive

// Reverses the byte order of `count` values of `size` bytes each, in place.
void swapBytes(std::byte* data, std::size_t count, std::size_t size);

}  // namespace isoatlas
