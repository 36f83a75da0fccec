// INRIMAGE-4 (.inr, .inr.gz), CGAL's volume format: a text header of KEY=VALUE lines in blocks of
// 256 bytes, from "#INRIMAGE-4#{" to "##}", then raw voxels. Read by hand; the header is tiny.
// Keys used: XDIM YDIM ZDIM VDIM TYPE PIXSIZE CPU VX VY VZ, and TX TY TZ (origin) as CGAL writes them.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/volume_io.h"

namespace isoatlas {
namespace {

constexpr std::size_t kBlock = 256;
constexpr std::size_t kMaxHeaderBlocks = 64;  // 16 KiB of header is far past any real file

double parseNumber(const std::map<std::string, std::string>& keys, const std::string& key, double fallback,
                   const std::string& where) {
  auto it = keys.find(key);
  if (it == keys.end()) return fallback;
  char* end = nullptr;
  const double value = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || !std::isfinite(value))
    throw Error(where + ": INR header " + key + "=" + it->second + " is not a number");
  return value;
}

std::int64_t parseDim(const std::map<std::string, std::string>& keys, const std::string& key, const std::string& where) {
  const double value = parseNumber(keys, key, 1, where);
  if (value > 9e15) throw Error(where + ": INR header " + key + "=" + keys.at(key) + " is too large");
  if (value != std::floor(value) || value < 1)
    throw Error(where + ": INR header " + key + "=" + keys.at(key) + " is not a positive whole number");
  return std::int64_t(value);
}

}  // namespace

Volume readInr(const std::string& path) {
  GzFile file(path, "rb");
  std::string header;
  for (std::size_t block = 0;; ++block) {
    if (block == kMaxHeaderBlocks) throw Error(path + ": INR header has no end marker \"##}\" in its first 16 KiB");
    char buf[kBlock];
    const std::size_t got = file.read(buf, kBlock);
    header.append(buf, got);
    if (block == 0 && header.rfind("#INRIMAGE-4#{", 0) != 0)
      throw Error(path + ": not an INR file (it does not start with #INRIMAGE-4#{)");
    if (got < kBlock) throw Error(path + ": truncated INR header (" + std::to_string(header.size()) + " bytes)");
    if (header.find("##}") != std::string::npos) break;
  }

  std::map<std::string, std::string> keys;
  std::istringstream lines(header.substr(0, header.find("##}")));
  std::string line;
  while (std::getline(lines, line)) {
    const auto eq = line.find('=');
    if (line.empty() || line[0] == '#' || eq == std::string::npos) continue;
    keys[line.substr(0, eq)] = line.substr(eq + 1);
  }

  Volume v;
  v.dims = {parseDim(keys, "XDIM", path), parseDim(keys, "YDIM", path), parseDim(keys, "ZDIM", path)};
  if (parseDim(keys, "VDIM", path) != 1) throw Error(path + ": INR VDIM=" + keys["VDIM"] + "; isoatlas reads scalar volumes");
  const std::string type = keys.count("TYPE") ? keys["TYPE"] : "";
  const std::string pixsize = keys.count("PIXSIZE") ? keys["PIXSIZE"] : "";
  int bits = 0;
  if (std::sscanf(pixsize.c_str(), "%d bits", &bits) != 1) throw Error(path + ": INR PIXSIZE=\"" + pixsize + "\" is not \"N bits\"");
  if (type == "float" && bits == 32) v.type = ScalarType::Float32;
  else if (type == "float" && bits == 64) v.type = ScalarType::Float64;
  else if (type == "unsigned fixed" && bits == 8) v.type = ScalarType::UInt8;
  else if (type == "unsigned fixed" && bits == 16) v.type = ScalarType::UInt16;
  else if (type == "unsigned fixed" && bits == 32) v.type = ScalarType::UInt32;
  else if (type == "signed fixed" && bits == 8) v.type = ScalarType::Int8;
  else if (type == "signed fixed" && bits == 16) v.type = ScalarType::Int16;
  else if (type == "signed fixed" && bits == 32) v.type = ScalarType::Int32;
  else throw Error(path + ": unsupported INR voxel type TYPE=\"" + type + "\" PIXSIZE=\"" + pixsize + "\"");
  v.spacing = {parseNumber(keys, "VX", 1, path), parseNumber(keys, "VY", 1, path), parseNumber(keys, "VZ", 1, path)};
  v.origin = {parseNumber(keys, "TX", 0, path), parseNumber(keys, "TY", 0, path), parseNumber(keys, "TZ", 0, path)};
  validateVolumeHeader(v, path);

  const std::string cpu = keys.count("CPU") ? keys["CPU"] : "decm";
  bool bigEndian;
  if (cpu == "decm" || cpu == "pc" || cpu == "alpha") bigEndian = false;
  else if (cpu == "sun" || cpu == "sgi" || cpu == "mips") bigEndian = true;
  else throw Error(path + ": unknown INR byte order CPU=" + cpu);

  v.data = file.readExactly(v.voxelCount() * bytesPerVoxel(v.type), path);
  const std::uint16_t probe = 1;
  const bool hostBig = *reinterpret_cast<const std::uint8_t*>(&probe) == 0;
  if (bigEndian != hostBig) swapBytes(v.data.data(), v.voxelCount(), bytesPerVoxel(v.type));
  return v;
}

void writeInr(const std::string& path, const Volume& v) {
  if (!(v.direction == Mat3{}))
    throw Error(path + ": INR cannot store an oriented volume (its direction is not the identity); "
                "write .nii.gz or .nrrd instead");
  const char* type = isFloating(v.type) ? "float"
                     : (v.type == ScalarType::Int8 || v.type == ScalarType::Int16 || v.type == ScalarType::Int32)
                         ? "signed fixed" : "unsigned fixed";
  std::ostringstream h;
  h.precision(17);
  h << "#INRIMAGE-4#{\n"
    << "XDIM=" << v.dims[0] << "\nYDIM=" << v.dims[1] << "\nZDIM=" << v.dims[2] << "\nVDIM=1\n"
    << "TYPE=" << type << "\nPIXSIZE=" << bytesPerVoxel(v.type) * 8 << " bits\n"
    << (isFloating(v.type) ? "" : "SCALE=2**0\n") << "CPU=decm\n"
    << "VX=" << v.spacing.x << "\nVY=" << v.spacing.y << "\nVZ=" << v.spacing.z << "\n"
    << "TX=" << v.origin.x << "\nTY=" << v.origin.y << "\nTZ=" << v.origin.z << "\n";
  std::string header = h.str();
  const std::string end = "##}\n";
  const std::size_t total = (header.size() + end.size() + kBlock - 1) / kBlock * kBlock;
  header.append(total - header.size() - end.size(), '\n');
  header += end;

  GzFile file(path, endsWith(path, ".gz") ? "wb6" : "wbT");
  file.write(header.data(), header.size());
  file.write(v.data.data(), v.data.size());  // little-endian hosts only write "decm"
  file.close();
}

}  // namespace isoatlas
