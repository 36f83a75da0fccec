// isoatlas.Volume, read_volume, write_volume: volumes between numpy (x, y, z arrays with nibabel's
// affine) and isoatlas's Volume (x fastest, RAS mm).
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "core/volume_io.h"
#include "python/bindings.h"

namespace isoatlas::python {
namespace {

py::dtype dtypeOf(ScalarType t) {
  switch (t) {
    case ScalarType::UInt8: return py::dtype::of<std::uint8_t>();
    case ScalarType::Int8: return py::dtype::of<std::int8_t>();
    case ScalarType::UInt16: return py::dtype::of<std::uint16_t>();
    case ScalarType::Int16: return py::dtype::of<std::int16_t>();
    case ScalarType::UInt32: return py::dtype::of<std::uint32_t>();
    case ScalarType::Int32: return py::dtype::of<std::int32_t>();
    case ScalarType::Float32: return py::dtype::of<float>();
    case ScalarType::Float64: return py::dtype::of<double>();
  }
  throw Error("unknown scalar type", ErrorKind::Failure);
}

ScalarType scalarTypeOf(const py::dtype& d, const char* what) {
  const char kind = d.kind();
  const auto size = d.itemsize();
  if (kind == 'b') return ScalarType::UInt8;
  if (kind == 'u' && size == 1) return ScalarType::UInt8;
  if (kind == 'i' && size == 1) return ScalarType::Int8;
  if (kind == 'u' && size == 2) return ScalarType::UInt16;
  if (kind == 'i' && size == 2) return ScalarType::Int16;
  if (kind == 'u' && size == 4) return ScalarType::UInt32;
  if (kind == 'i' && size == 4) return ScalarType::Int32;
  if (kind == 'f' && size == 4) return ScalarType::Float32;
  if (kind == 'f' && size == 8) return ScalarType::Float64;
  throw Error(std::string(what) + ": a volume's voxels are (u)int8, (u)int16, (u)int32, float32 or float64, not " +
              py::str(static_cast<const py::handle&>(d)).cast<std::string>());
}

// Spacing, direction and origin from a 4x4 affine (columns: the voxel axes in world mm).
void setGeometry(Volume& v, const py::object& affine, const char* what) {
  if (affine.is_none()) return;  // identity: 1 mm voxels at the origin
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(affine);
  require(a && a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4, std::string(what) + ": the affine must be a 4 x 4 array");
  const auto m = a.unchecked<2>();
  for (int c = 0; c < 3; ++c) {
    const double s = std::sqrt(m(0, c) * m(0, c) + m(1, c) * m(1, c) + m(2, c) * m(2, c));
    require(std::isfinite(s) && s > 0, std::string(what) + ": the affine's column " + std::to_string(c) + " is not a voxel axis");
    v.spacing[c] = s;
    for (int r = 0; r < 3; ++r) v.direction.m[r][c] = m(r, c) / s;
  }
  v.origin = {m(0, 3), m(1, 3), m(2, 3)};
}

}  // namespace

py::array voxelArray(const Volume& v, const py::object& owner) {
  const auto b = py::ssize_t(bytesPerVoxel(v.type));
  return py::array(dtypeOf(v.type), {py::ssize_t(v.dims[0]), py::ssize_t(v.dims[1]), py::ssize_t(v.dims[2])},
                   {b, b * py::ssize_t(v.dims[0]), b * py::ssize_t(v.dims[0] * v.dims[1])}, v.data.data(), owner);
}

py::array affineOf(const Volume& v) {
  py::array_t<double> a({4, 4});
  auto m = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = r == 3 ? (c == 3 ? 1 : 0) : c == 3 ? v.origin[r] : v.direction.m[r][c] * v.spacing[c];
  return a;
}

Volume toVolume(const py::object& object, const py::object& affine, const char* what) {
  if (py::isinstance<Volume>(object)) return object.cast<const Volume&>();
  if (py::hasattr(object, "dataobj") && py::hasattr(object, "affine"))  // a nibabel image
    return toVolume(py::module_::import("numpy").attr("asanyarray")(object.attr("dataobj")), object.attr("affine"), what);
  const py::array array = py::module_::import("numpy").attr("asarray")(object);
  require(array.ndim() == 3, std::string(what) + ": a volume is a 3D array (x, y, z), not " + std::to_string(array.ndim()) + "D");
  const ScalarType type = scalarTypeOf(array.dtype(), what);
  // x fastest, as Fortran lays out (x, y, z); bool as uint8.
  py::array fortran = py::module_::import("numpy").attr("asfortranarray")(array, dtypeOf(type));
  Volume v;
  v.dims = {array.shape(0), array.shape(1), array.shape(2)};
  v.type = type;
  setGeometry(v, affine, what);
  validateVolumeHeader(v, what);
  v.data.resize(v.voxelCount() * bytesPerVoxel(type));
  std::memcpy(v.data.data(), fortran.data(), v.data.size());
  v.nonFiniteVoxels = backgroundNonFiniteVoxels(v, what).count;  // as readVolume reads them
  return v;
}

VolumeArgument::VolumeArgument(const py::object& object, const py::object& affine, const char* what) : object_(object) {
  if (py::isinstance<Volume>(object)) {  // its own affine, as toVolume takes it
    volume_ = &object.cast<const Volume&>();
  } else {
    converted_ = toVolume(object, affine, what);
    volume_ = &*converted_;
  }
}

void bindVolumes(py::module_& m) {
  py::class_<Volume>(m, "Volume", "a 3D scan or mask: .data (x, y, z) shares the voxels; .affine as nibabel reports it")
      .def(py::init([](const py::object& data, const py::object& affine) { return toVolume(data, affine, "Volume"); }),
           py::arg("data"), py::arg("affine") = py::none(), "a volume from an array (copied, any layout) and its affine")
      .def_property_readonly("data", [](py::object self) { return voxelArray(self.cast<const Volume&>(), self); })
      .def_property_readonly("affine", [](const Volume& v) { return affineOf(v); })
      .def_property_readonly("spacing", [](const Volume& v) { return std::array<double, 3>{v.spacing.x, v.spacing.y, v.spacing.z}; })
      .def_property_readonly("shape", [](const Volume& v) { return v.dims; })
      .def_property_readonly("non_finite_voxels", [](const Volume& v) { return v.nonFiniteVoxels; },
                             "NaN or infinite voxels it was given, read as the background (its smallest finite value)")
      .def("__repr__", [](const Volume& v) {
        return "<isoatlas.Volume " + std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " + std::to_string(v.dims[2]) +
               " " + scalarTypeName(v.type) + ">";
      });
  m.def("read_volume", [](const std::string& path, std::optional<std::int64_t> volume, const std::string& series) {
        requireFile(path);
        require(!volume || *volume >= 0, "read_volume: volume must be 0 or more, not " + std::to_string(volume.value_or(0)));
        return readVolume(path, {.volume = volume.value_or(-1), .series = series});
      }, py::arg("path"), py::arg("volume") = py::none(), py::arg("series") = "",
      "NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr), INR (.inr, .inr.gz), or a DICOM folder (or a .dcm file of one); "
      "volume: which of a 4D series, from 0; series: which DICOM series of the folder (its SeriesInstanceUID)");
  m.def("write_volume", [](const std::string& path, const py::object& volume, const py::object& affine) {
        writeVolume(path, VolumeArgument(volume, affine, "write_volume").get());
      }, py::arg("path"), py::arg("volume"), py::arg("affine") = py::none(), "a Volume, or an array with its affine");
}

}  // namespace isoatlas::python
