// The `isoatlas` Python module's native part (python/isoatlas/__init__.py is the rest). Errors:
// isoatlas::Error of bad input becomes ValueError with the CLI's message, of failed work RuntimeError.
#include <tbb/global_control.h>

#include <memory>

#include "core/error.h"
#include "core/memory_budget.h"
#include "core/progress.h"
#include "python/bindings.h"

namespace {

// The process's cap on the library's threads (TBB's), kept while the process lives; none: every core.
void setThreads(int threads) {
  static std::unique_ptr<tbb::global_control> cap;
  isoatlas::require(threads >= 0, "set_threads: a thread count >= 0 (0: every core)");
  cap.reset();
  if (threads > 0) cap = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
}

}  // namespace

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
  m.def("set_threads", &setThreads, py::arg("threads"),
        "at most this many threads for the library's parallel work in this process (0: every core); the cohort's workers "
        "take one each, so that N workers share N cores");
  m.def(
      "set_max_memory",
      [](py::object size) {
        isoatlas::setMemoryBudget(py::isinstance<py::str>(size) ? isoatlas::parseByteSize(size.cast<std::string>())
                                                                 : isoatlas::parseByteSize(std::to_string(size.cast<double>())));
      },
      py::arg("size"),
      "the most memory one input may take once read (a volume's voxels, a model's charts), in bytes or as '8G', '512M' (the "
      "command's --max-memory); default half the physical memory");
  m.def("max_memory", &isoatlas::memoryBudget, "the memory budget in bytes (set_max_memory)");
  isoatlas::python::bindVolumes(m);
  isoatlas::python::bindStages(m);
  isoatlas::python::bindModels(m);
  isoatlas::python::bindMeshes(m);
}
