// DICOM series in, through GDCM: the one file that includes its headers. The folder's files are
// scanned for the tags that place each slice (one slice a file, the classic layout scanners write),
// then read one by one into the volume. Geometry: voxel (i, j, k) lies at
// ImagePositionPatient(slice k) + i * PixelSpacing[1] * row + j * PixelSpacing[0] * column, row and
// column being ImageOrientationPatient's two directions, slices sorted along row x column; DICOM's
// LPS is turned into RAS. Rescale slope and intercept are applied (float32 when a slice has any).
#include <gdcmDirectory.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmScanner.h>
#include <gdcmTrace.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/volume_io.h"

namespace isoatlas {
namespace {

const gdcm::Tag kSeriesUid(0x0020, 0x000e), kPosition(0x0020, 0x0032), kOrientation(0x0020, 0x0037),
    kPixelSpacing(0x0028, 0x0030), kRows(0x0028, 0x0010), kColumns(0x0028, 0x0011), kFrames(0x0028, 0x0008),
    kSamples(0x0028, 0x0002), kTilt(0x0018, 0x1120), kSlope(0x0028, 0x1053), kIntercept(0x0028, 0x1052),
    kSliceThickness(0x0018, 0x0050);

// A backslash-separated DICOM number list ("0.5\0.5"); empty for a missing or unreadable value.
std::vector<double> numbers(const char* text) {
  std::vector<double> out;
  if (!text) return out;
  std::string s(text);
  std::replace(s.begin(), s.end(), '\\', ' ');
  std::istringstream in(s);
  in.imbue(std::locale::classic());
  for (double x; in >> x;) out.push_back(x);
  return out;
}

double numberOr(const char* text, double fallback) {
  const auto n = numbers(text);
  return n.empty() || !std::isfinite(n[0]) ? fallback : n[0];
}

// Whether two number lists are the same within `tolerance` each.
bool near(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!(std::abs(a[k] - b[k]) <= tolerance)) return false;
  return true;
}

std::string trimmed(const char* text) {
  std::string s = text ? text : "";
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  return s;
}

ScalarType scalarTypeOf(const gdcm::PixelFormat& format, const std::string& file) {
  switch (format.GetScalarType()) {
    case gdcm::PixelFormat::UINT8: return ScalarType::UInt8;
    case gdcm::PixelFormat::INT8: return ScalarType::Int8;
    case gdcm::PixelFormat::UINT16: return ScalarType::UInt16;
    case gdcm::PixelFormat::INT16: return ScalarType::Int16;
    case gdcm::PixelFormat::UINT32: return ScalarType::UInt32;
    case gdcm::PixelFormat::INT32: return ScalarType::Int32;
    case gdcm::PixelFormat::FLOAT32: return ScalarType::Float32;
    case gdcm::PixelFormat::FLOAT64: return ScalarType::Float64;
    default: throw Error(file + ": DICOM pixels of type " + format.GetScalarTypeAsString() + " are not supported");
  }
}

struct Slice {
  std::string file;
  Vec3 position;  // LPS
  double along = 0;  // position along the slice normal
  double slope = 1, intercept = 0;
};

// The series' files, given a folder (searched with its subfolders, as a study or PACS export lays
// out its series) or a file of one (its own folder's files), and the UID asked for (empty: the only
// one there). Files without a SeriesInstanceUID (a DICOMDIR, say) are no series' slices: passed over.
std::vector<Slice> seriesSlices(const std::string& path, const std::string& series, gdcm::Scanner& scanner) {
  std::error_code ec;
  const bool folder = std::filesystem::is_directory(path, ec);
  const std::string dir = folder ? path : std::filesystem::path(path).parent_path().string();
  gdcm::Directory directory;
  directory.Load(dir.empty() ? "." : dir, folder);
  for (const gdcm::Tag& t : {kSeriesUid, kPosition, kOrientation, kPixelSpacing, kRows, kColumns, kFrames, kSamples, kTilt, kSlope,
                             kIntercept, kSliceThickness})
    scanner.AddTag(t);
  require(scanner.Scan(directory.GetFilenames()), path + ": could not scan the folder's DICOM files");
  std::map<std::string, std::vector<std::string>> bySeries;
  for (const std::string& file : directory.GetFilenames()) {
    if (!scanner.IsKey(file.c_str())) continue;
    const std::string uid = trimmed(scanner.GetValue(file.c_str(), kSeriesUid));
    if (!uid.empty()) bySeries[uid].push_back(file);
  }
  if (bySeries.empty()) throw Error(path + ": " + (folder ? "the folder (with its subfolders) holds no DICOM series" : "is not a slice of a DICOM series"));
  std::string uid = series;
  if (uid.empty() && !folder) uid = trimmed(scanner.GetValue(path.c_str(), kSeriesUid));
  if (uid.empty()) {
    if (bySeries.size() > 1) {
      std::string list;
      for (const auto& [id, files] : bySeries) list += (list.empty() ? "" : ", ") + id + " (" + std::to_string(files.size()) + " files)";
      throw Error(path + ": holds " + std::to_string(bySeries.size()) + " DICOM series; pick one with --series UID: " + list);
    }
    uid = bySeries.begin()->first;
  }
  const auto found = bySeries.find(uid);
  if (found == bySeries.end()) throw Error(path + ": holds no DICOM series " + uid + " (--series)");
  std::vector<Slice> slices;
  for (const std::string& file : found->second) {
    const char* f = file.c_str();
    Slice s{file};
    const auto p = numbers(scanner.GetValue(f, kPosition));
    if (p.size() != 3) throw Error(file + ": no ImagePositionPatient: isoatlas needs each slice's place");
    s.position = {p[0], p[1], p[2]};
    s.slope = numberOr(scanner.GetValue(f, kSlope), 1);
    s.intercept = numberOr(scanner.GetValue(f, kIntercept), 0);
    slices.push_back(s);
  }
  return slices;
}

// The files GDCM is about to parse, one name a line on `fd` (the child's pipe; -1: none), and at
// the end the error, if any, after an 'E'.
void announce(int fd, const std::string& line) {
  if (fd < 0) return;
  const std::string text = line + "\n";
  if (::write(fd, text.data(), text.size()) < 0) {}  // the parent reads what it can
}

Volume readDicomHere(const std::string& path, const std::string& series, int announceFd);

// GDCM asserts, and can crash, on damaged files (Debian builds it with its assertions on), so the
// whole read is first done in a child process, which reports each file before parsing it: if the
// child dies, the parent names the file, as one clear error, and its own process lives on. The
// child's Error is the parent's (nor does the parent then parse the files: what made GDCM
// allocate wildly stays in the child). Only a series the child read whole does the parent read
// itself. Costs the read twice (the child's volume is thrown away), a small price next to a
// crashed viewer or a lost cohort worker.
void requireReadableInAChild(const std::string& path, const std::string& series) {
  int fds[2];
  if (::pipe(fds) != 0) return;  // no pipe, no child: read in-process
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]), ::close(fds[1]);
    return;
  }
  if (child == 0) {
    ::close(fds[0]);
    // GDCM's assertion lines would speak past the parent's one line.
    if (const int quiet = ::open("/dev/null", O_WRONLY); quiet >= 0) ::dup2(quiet, 2);
    int code = 0;
    try {
      readDicomHere(path, series, fds[1]);
    } catch (const Error& e) {
      announce(fds[1], std::string("E") + e.what());
      code = 1;
    } catch (...) {  // memory, most likely
      code = 2;
    }
    ::_exit(code);
  }
  ::close(fds[1]);
  std::string announced;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) != 0;)
    if (n > 0) announced.append(buffer, std::size_t(n));
    else if (errno != EINTR) break;
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {}
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (!announced.empty() && announced.back() == '\n') announced.pop_back();
  const std::size_t newline = announced.find_last_of('\n');
  const std::string last = announced.substr(newline == std::string::npos ? 0 : newline + 1);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 1 && last.starts_with("E")) throw Error(last.substr(1));
  const std::string file = last.empty() || last.starts_with("E") ? path : last;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2) throw Error(file + ": ran out of memory reading this DICOM file");
  throw Error(file + ": a damaged DICOM file (GDCM failed on it); isoatlas read nothing");
}

}  // namespace

bool isDicomPath(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) || endsWith(path, ".dcm") || endsWith(path, ".DCM");
}

Volume readDicom(const std::string& path, const std::string& series) {
  requireReadableInAChild(path, series);
  return readDicomHere(path, series, -1);
}

namespace {

// readDicom in this process; announceFd: where to name each file before GDCM parses it (the
// child's pipe), and then no progress (the child must not take the progress observer's lock,
// which another thread may have held across the fork).
Volume readDicomHere(const std::string& path, const std::string& series, int announceFd) {
  gdcm::Trace::SetWarning(false);  // GDCM's own lines on stderr would speak past ours
  gdcm::Trace::SetDebug(false);
  gdcm::Trace::SetError(false);
  gdcm::Scanner scanner;
  announce(announceFd, path);
  std::vector<Slice> slices = seriesSlices(path, series, scanner);
  const char* first = slices[0].file.c_str();
  const auto orientation = numbers(scanner.GetValue(first, kOrientation));
  const auto pixelSpacing = numbers(scanner.GetValue(first, kPixelSpacing));
  if (orientation.size() != 6) throw Error(slices[0].file + ": no ImageOrientationPatient: isoatlas needs the slices' directions");
  if (pixelSpacing.size() != 2 || !(pixelSpacing[0] > 0) || !(pixelSpacing[1] > 0))
    throw Error(slices[0].file + ": no PixelSpacing: isoatlas needs the voxel size");
  const Vec3 row{orientation[0], orientation[1], orientation[2]}, column{orientation[3], orientation[4], orientation[5]};
  const Vec3 normal = cross(row, column);
  if (!(std::abs(norm(row) - 1) < 1e-3 && std::abs(norm(column) - 1) < 1e-3 && std::abs(dot(row, column)) < 1e-3))
    throw Error(slices[0].file + ": ImageOrientationPatient is not two unit, perpendicular directions");
  for (const Slice& s : slices) {
    const char* f = s.file.c_str();
    if (!near(numbers(scanner.GetValue(f, kOrientation)), orientation, 1e-4))
      throw Error(path + ": the series' slices lie in different orientations (" + s.file + ")");
    if (numbers(scanner.GetValue(f, kPixelSpacing)) != pixelSpacing || trimmed(scanner.GetValue(f, kRows)) != trimmed(scanner.GetValue(first, kRows)) ||
        trimmed(scanner.GetValue(f, kColumns)) != trimmed(scanner.GetValue(first, kColumns)))
      throw Error(path + ": the series' slices differ in size or pixel spacing (" + s.file + ")");
    if (numberOr(scanner.GetValue(f, kFrames), 1) > 1)
      throw Error(s.file + ": a multi-frame DICOM file; isoatlas reads a series of one slice a file (convert it with dcm2niix)");
    if (numberOr(scanner.GetValue(f, kSamples), 1) != 1) throw Error(s.file + ": colour DICOM pixels; isoatlas reads one value a voxel");
    const double tilt = numberOr(scanner.GetValue(f, kTilt), 0);
    if (tilt != 0) throw Error(path + ": gantry tilt of " + shortNumber(tilt) + " degrees; isoatlas needs slices stacked straight (resample with dcm2niix)");
  }
  for (Slice& s : slices) s.along = dot(s.position, normal);
  std::sort(slices.begin(), slices.end(), [](const Slice& a, const Slice& b) { return a.along < b.along; });
  double step = numberOr(scanner.GetValue(first, kSliceThickness), 1);
  if (slices.size() > 1) {
    const double total = slices.back().along - slices.front().along;
    step = total / double(slices.size() - 1);
    if (!(step > 1e-6)) throw Error(path + ": several slices lie at one place (a series of several echoes or time points); isoatlas needs one volume");
    for (std::size_t k = 1; k < slices.size(); ++k) {
      const double gap = slices[k].along - slices[k - 1].along;
      if (std::abs(gap - step) > 0.01 * step + 1e-4)
        throw Error(path + ": uneven slice spacing (" + shortNumber(gap) + " mm between slices " + std::to_string(k - 1) + " and " +
                    std::to_string(k) + ", " + shortNumber(step) + " mm on average); isoatlas needs evenly spaced slices");
      // Slices stacked along the normal: a position off it is a tilted or sheared stack.
      const Vec3 off = slices[k].position - slices[0].position - normal * (slices[k].along - slices[0].along);
      if (norm(off) > 0.01 * step * double(k) + 1e-3)
        throw Error(path + ": the slices are not stacked along their normal (a gantry tilt of about " +
                    shortNumber(std::atan2(norm(off), slices[k].along - slices[0].along) * 180 / M_PI) +
                    " degrees); isoatlas needs slices stacked straight (resample with dcm2niix)");
    }
  }
  // Each slice's pixels, GDCM's reader holding them; the first slice's, read once, gives the
  // stored type (the rescale decides whether the volume is float32).
  auto readSlice = [&](std::size_t k) {
    announce(announceFd, slices[k].file);
    auto reader = std::make_unique<gdcm::ImageReader>();
    reader->SetFileName(slices[k].file.c_str());
    if (!reader->Read()) throw Error(slices[k].file + ": GDCM could not read its pixel data");
    return reader;
  };
  std::unique_ptr<gdcm::ImageReader> firstReader = readSlice(0);
  const ScalarType stored = scalarTypeOf(firstReader->GetImage().GetPixelFormat(), slices[0].file);
  const bool rescaled = std::any_of(slices.begin(), slices.end(), [](const Slice& s) { return s.slope != 1 || s.intercept != 0; });
  Volume v;
  v.dims = {std::int64_t(numberOr(scanner.GetValue(first, kColumns), 0)), std::int64_t(numberOr(scanner.GetValue(first, kRows), 0)),
            std::int64_t(slices.size())};
  v.type = rescaled ? ScalarType::Float32 : stored;
  // LPS to RAS: x and y change sign.
  auto ras = [](const Vec3& p) { return Vec3{-p.x, -p.y, p.z}; };
  Mat3 linear;
  const Vec3 axes[3] = {ras(row) * pixelSpacing[1], ras(column) * pixelSpacing[0], ras(normal) * step};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) linear.m[r][c] = axes[c][r];
  setGeometryFromAffine(v, linear, ras(slices[0].position), path);
  validateVolumeHeader(v, path);  // every size, before the voxels are allocated
  v.data.resize(v.voxelCount() * bytesPerVoxel(v.type));
  const std::size_t sliceVoxels = std::size_t(v.dims[0] * v.dims[1]), storedBytes = sliceVoxels * bytesPerVoxel(stored);
  std::vector<char> buffer;
  Volume slice;  // one stored slice, to convert through Volume::value
  slice.dims = {v.dims[0], v.dims[1], 1};
  slice.type = stored;
  std::optional<Progress> progress;
  if (announceFd < 0) progress.emplace("dicom: reading " + path, slices.size(), "slices");
  for (std::size_t k = 0; k < slices.size(); ++k) {
    const std::unique_ptr<gdcm::ImageReader> reader = k == 0 ? std::move(firstReader) : readSlice(k);
    const gdcm::Image& image = reader->GetImage();
    if (std::int64_t(image.GetDimension(0)) != v.dims[0] || std::int64_t(image.GetDimension(1)) != v.dims[1] || scalarTypeOf(image.GetPixelFormat(), slices[k].file) != stored)
      throw Error(slices[k].file + ": its pixels differ in size or type from the series' first slice");
    if (image.GetBufferLength() != storedBytes) throw Error(slices[k].file + ": its pixel data has the wrong length");
    buffer.resize(storedBytes);
    if (!image.GetBuffer(buffer.data())) throw Error(slices[k].file + ": GDCM could not decode its pixel data");
    std::byte* to = v.data.data() + k * sliceVoxels * bytesPerVoxel(v.type);
    if (!rescaled) {
      std::memcpy(to, buffer.data(), storedBytes);
    } else {
      slice.data.assign(reinterpret_cast<const std::byte*>(buffer.data()), reinterpret_cast<const std::byte*>(buffer.data()) + storedBytes);
      float* out = reinterpret_cast<float*>(to);
      for (std::size_t n = 0; n < sliceVoxels; ++n) out[n] = float(slice.value(n) * slices[k].slope + slices[k].intercept);
    }
    if (progress) progress->update(k + 1);
  }
  if (progress) progress->finish();
  return v;
}

}  // namespace

}  // namespace isoatlas
