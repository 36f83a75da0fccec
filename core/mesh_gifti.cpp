#include "core/mesh_gifti.h"

extern "C" {  // a C library whose header does not say so
#include <gifti_io.h>
}

#include <cstdlib>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"

namespace isoatlas {
namespace {

struct ImageDeleter {
  void operator()(gifti_image* image) const { gifti_free_image(image); }
};

// Data array k of `image` as an n x 3 row-major array of `datatype` (NIFTI_TYPE_FLOAT32 or INT32).
giiDataArray* threeColumns(gifti_image* image, int k, int intent, int datatype, std::size_t rows) {
  giiDataArray* array = image->darray[k];
  gifti_set_DA_defaults(array);
  array->intent = intent;
  array->datatype = datatype;
  array->ind_ord = GIFTI_IND_ORD_ROW_MAJOR;
  array->num_dim = 2;
  array->dims[0] = int(rows);
  array->dims[1] = 3;
  array->encoding = GIFTI_ENCODING_B64GZ;
  array->endian = GIFTI_ENDIAN_LITTLE;
  array->nvals = (long long)(rows * 3);
  array->nbyper = 4;
  array->data = std::calloc(rows * 3, 4);  // gifti_free_image frees it
  if (!array->data) throw Error("out of memory for a GIfTI array", ErrorKind::Failure);
  return array;
}

}  // namespace

void writeGiftiMesh(const std::string& path, const Mesh& mesh) {
  require(mesh.faceCount() > 0, path + ": refusing to write a mesh with no faces");
  require(mesh.allFacesHave(3), path + ": a GIfTI surface holds triangles; this mesh has larger faces");
  require(mesh.vertexCount() < std::size_t(1) << 31 && mesh.faceCount() < std::size_t(1) << 31, path + ": too many vertices or faces for GIfTI");
  gifti_set_verb(0);  // its own chatter would break the one-line error contract
  std::unique_ptr<gifti_image, ImageDeleter> image(gifti_create_image(0, NIFTI_INTENT_NONE, NIFTI_TYPE_FLOAT32, 0, nullptr, 0));
  if (!image || gifti_add_empty_darray(image.get(), 2) != 0) throw Error(path + ": libgiftiio could not make an image", ErrorKind::Failure);

  giiDataArray* points = threeColumns(image.get(), 0, NIFTI_INTENT_POINTSET, NIFTI_TYPE_FLOAT32, mesh.vertexCount());
  float* xyz = static_cast<float*>(points->data);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    for (int a = 0; a < 3; ++a) xyz[3 * v + std::size_t(a)] = float(mesh.positions[v][a]);
  if (gifti_add_empty_CS(points) != 0) throw Error(path + ": libgiftiio could not add a coordinate system", ErrorKind::Failure);
  giiCoordSystem* frame = points->coordsys[0];
  frame->dataspace = gifti_strdup("NIFTI_XFORM_SCANNER_ANAT");
  frame->xformspace = gifti_strdup("NIFTI_XFORM_SCANNER_ANAT");
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) frame->xform[r][c] = r == c ? 1 : 0;

  giiDataArray* triangles = threeColumns(image.get(), 1, NIFTI_INTENT_TRIANGLE, NIFTI_TYPE_INT32, mesh.faceCount());
  std::int32_t* corners = static_cast<std::int32_t*>(triangles->data);
  for (std::size_t k = 0; k < mesh.faceVertices.size(); ++k) corners[k] = std::int32_t(mesh.faceVertices[k]);

  writeAtomically(path, [&](const std::string& to) {
    if (gifti_write_image(image.get(), to.c_str(), 1) != 0) throw Error(path + ": could not write the GIfTI surface", ErrorKind::Failure);
  });
}

}  // namespace isoatlas
