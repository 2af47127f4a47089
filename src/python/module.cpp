// The module definition: the InputError exception, the array helpers, and every binding.
#include <omp.h>
#include <pthread.h>

#include <atomic>
#include <cmath>
#include <stdexcept>

#include "armstudy/version.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

Rows readRows(const py::handle& object, long cols, const char* what) {
  Rows r;
  r.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!r.array) throw std::invalid_argument(std::string(what) + ": expected an array of numbers");
  r.cols = cols;
  if (r.array.ndim() == 1 && r.array.shape(0) == cols) {
    r.single = true;
    r.n = 1;
  } else if (r.array.ndim() == 2 && r.array.shape(1) == cols) {
    r.n = static_cast<long>(r.array.shape(0));
  } else {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < r.array.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(r.array.shape(d));
    throw std::invalid_argument(std::string(what) + ": expected shape (" + std::to_string(cols) +
                                ",) or (N, " + std::to_string(cols) + "), got " + shape +
                                (r.array.ndim() == 1 ? ",)" : ")"));
  }
  const double* p = r.array.data();
  for (long i = 0; i < r.n * cols; ++i)
    if (!std::isfinite(p[i]))
      throw std::invalid_argument(std::string(what) + ": row " + std::to_string(i / cols) +
                                  ", column " + std::to_string(i % cols) + " is not finite");
  return r;
}

py::array_t<double> makeResult(const Rows& rows, std::vector<py::ssize_t> extra) {
  if (!rows.single) extra.insert(extra.begin(), rows.n);
  return py::array_t<double>(extra);
}

void checkArgument(const char* name, long long value, long long lo, long long hi,
                   const char* note) {
  if (value < lo || value > hi)
    throw InputError("arguments", 0, name,
                     "must be within " + std::to_string(lo) + ".." + std::to_string(hi) + note +
                         ", got " + std::to_string(value));
}

namespace {
std::atomic<bool> forked_child{false};
// The pthread_atfork child handler: from now on one thread per region (bindings.hpp).
void afterFork() {
  forked_child = true;
  omp_set_num_threads(1);
}
}  // namespace

bool forkedChild() { return forked_child; }

py::object pathLike(const py::object& o) {
  if (py::isinstance<py::str>(o) || !py::hasattr(o, "__fspath__")) return o;
  return py::module_::import("os").attr("fspath")(o);
}

int threadCount(int threads) {
  checkArgument("threads", threads, 0, defaults::kMaxThreads, " (0 = all cores)");
  if (forkedChild()) return 1;
  return threads > 0 ? threads : std::max(1, omp_get_max_threads());
}

}  // namespace armstudy::python

PYBIND11_MODULE(armstudy, m) {
  using namespace armstudy::python;
  m.doc() =
      "armstudy: robot-arm design studies (reach, dexterity, collisions, dynamics) from Python. "
      "Designs, kernels on (N, dof) arrays, pose solves and whole studies run the engine's C++ "
      "code, so every number equals the armstudy CLI's. See docs/python.md.";
  pthread_atfork(nullptr, nullptr, &afterFork);
  m.attr("__version__") = armstudy::kVersion;
  m.attr("__revision__") = armstudy::kGitRevision;
  static py::exception<armstudy::InputError> input_error(m, "InputError", PyExc_ValueError);
  input_error.doc() =
      "Bad input in a design, study or data file (the CLI's exit 2). str() is the CLI's message; "
      "the attributes file, line (0 when none), key and message carry its parts.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const armstudy::InputError& e) {
      py::object error = py::reinterpret_borrow<py::object>(input_error.ptr())(e.what());
      error.attr("file") = e.file();
      error.attr("line") = e.line();
      error.attr("key") = e.key();
      error.attr("message") = e.message();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
  bindDesign(m);
  bindStudy(m);
  bindPoses(m);
  bindCalibration(m);
}
