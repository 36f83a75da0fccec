// The `isoatlas` Python module's native part (python/isoatlas/__init__.py is the rest). Errors:
// isoatlas::Error of bad input becomes ValueError with the CLI's message, of failed work RuntimeError.
#include "core/error.h"
#include "core/progress.h"
#include "python/bindings.h"

PYBIND11_MODULE(_isoatlas, m) {
  namespace py = pybind11;
  m.doc() = "isoatlas: segment a scan, edit it, extract and model its surface (see python/isoatlas/__init__.py)";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const isoatlas::Error& e) {
      PyErr_SetString(e.kind() == isoatlas::ErrorKind::BadInput ? PyExc_ValueError : PyExc_RuntimeError, e.what());
    }
  });
  m.def("set_quiet", &isoatlas::Progress::setQuiet, py::arg("quiet") = true,
        "no progress or log lines of the library's own on stderr (errors still raise): the cohort's workers report per stage instead");
  isoatlas::python::bindVolumes(m);
  isoatlas::python::bindStages(m);
  isoatlas::python::bindModels(m);
  isoatlas::python::bindMeshes(m);
}
