#pragma once
// The Python module `armstudy` (docs/python.md): pybind11 bindings over the engine's layers. The
// kernels run the library's own functions (one workspace per OpenMP thread, the GIL released); a
// bad input raises armstudy.InputError carrying the CLI's message, file, line and key.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "io/urdf_io.hpp"
#include "model/model.hpp"

namespace armstudy::python {

namespace py = pybind11;

// A loaded design: the frozen model and the URDF facts the way back to URDF needs.
struct Design {
  std::shared_ptr<const Model> model;
  UrdfInfo info;
  std::vector<std::string> warnings;  // notes of the URDF import (missing meshes, branches)
};

// Configurations as a C-contiguous (N, dof) array of doubles; a single (dof,) vector is one row.
// Throws ValueError (std::invalid_argument) for another shape or a non-finite value.
struct Rows {
  py::array_t<double, py::array::c_style | py::array::forcecast> array;
  long n = 0;
  bool single = false;  // the input was one vector: results drop the leading axis
  const double* row(long i) const { return array.data() + i * cols; }
  long cols = 0;
};
Rows readRows(const py::handle& object, long cols, const char* what);

// An array of shape (n, extra...) or (extra...) when rows.single.
py::array_t<double> makeResult(const Rows& rows, std::vector<py::ssize_t> extra);

// A module function's argument `name` within lo..hi (the CLI's bound for the same option), else
// InputError("arguments", 0, name, "must be within lo..hi<note>, got value").
void checkArgument(const char* name, long long value, long long lo, long long hi,
                   const char* note = "");

// OpenMP threads for a batch call: `threads` (0 = the OpenMP default), at least 1; InputError
// beyond the CLI's --threads bound. Always 1 in a process forked from this one (forkedChild).
int threadCount(int threads);

// True in a process forked (os.fork, a fork-based multiprocessing pool) after the module was
// imported. The OpenMP runtime (libgomp) is not fork-safe: a parallel region of more than one
// thread in the child waits forever for the parent's pool threads, which do not exist there. So a
// forked child runs every call on one thread (a pool is one process per core anyway).
bool forkedChild();

// `o` itself, or os.fspath(o) for an os.PathLike (pathlib.Path): what a path argument accepts.
py::object pathLike(const py::object& o);

void bindDesign(py::module_& m);
void bindKernels(py::class_<Design>& design);
void bindSolve(py::module_& m, py::class_<Design>& design);
void bindStudy(py::module_& m);
void bindPoses(py::module_& m);
void bindCalibration(py::module_& m);

}  // namespace armstudy::python
