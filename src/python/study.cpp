// Studies: run one from a file or from a dict (the same runner as `armstudy run`, so the same
// files), and read the maps it wrote back as arrays with their grid axes.
#include <pybind11/stl.h>
#include <toml++/toml.h>
#include <vtkAbstractArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/toml_reader.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace fs = std::filesystem;

namespace {

py::list stringList(vtkFieldData* fd, const char* name) {
  py::list out;
  auto* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  if (a)
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i) out.append(std::string(a->GetValue(i)));
  return out;
}

// "<array> <value>: <meaning>" legend lines as {array: {value: meaning}}.
py::dict parseLegend(const py::list& legend) {
  py::dict out;
  for (const auto& item : legend) {
    const std::string line = item.cast<std::string>();
    const auto colon = line.find(": ");
    const auto space = line.rfind(' ', colon);
    if (colon == std::string::npos || space == std::string::npos) continue;
    const std::string array = line.substr(0, space);
    long value = 0;
    try {
      value = std::stol(line.substr(space + 1, colon - space - 1));
    } catch (const std::exception&) {
      continue;
    }
    if (!out.contains(array)) out[py::str(array)] = py::dict();
    out[py::str(array)].cast<py::dict>()[py::int_(value)] = line.substr(colon + 2);
  }
  return out;
}

py::dict readMap(const std::string& path) {
  if (!fs::is_regular_file(path)) throw std::invalid_argument("no map file '" + path + "'");
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  double origin[3], spacing[3];
  image->GetDimensions(dims);
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  py::dict out, axes, arrays;
  const char* axis_names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    py::array_t<double> a(dims[k]);
    for (int i = 0; i < dims[k]; ++i) a.mutable_at(i) = origin[k] + i * spacing[k];
    axes[axis_names[k]] = a;
  }
  vtkPointData* pd = image->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a) {
    vtkDataArray* data = pd->GetArray(a);
    if (!data) continue;
    const int c = data->GetNumberOfComponents();
    std::vector<py::ssize_t> shape = {dims[2], dims[1], dims[0]};
    if (c > 1) shape.push_back(c);
    py::array_t<double> values(shape);
    double* v = values.mutable_data();
    const vtkIdType n = data->GetNumberOfTuples();
    for (vtkIdType i = 0; i < n; ++i)
      for (int k = 0; k < c; ++k) v[i * c + k] = data->GetComponent(i, k);
    arrays[data->GetName()] = values;
  }
  out["file"] = path;
  out["dims"] = py::make_tuple(dims[0], dims[1], dims[2]);
  out["origin"] = py::make_tuple(origin[0], origin[1], origin[2]);
  out["spacing"] = py::make_tuple(spacing[0], spacing[1], spacing[2]);
  out["axes"] = axes;
  out["arrays"] = arrays;
  out["units"] = stringList(image->GetFieldData(), "units");
  const py::list legend = stringList(image->GetFieldData(), "legend");
  out["legend"] = legend;
  out["names"] = parseLegend(legend);
  return out;
}

// ---- a study given as a dict: TOML text, and key paths in its messages ----

void insertValue(toml::table& t, const std::string& key, const py::handle& v,
                 const std::string& at);

toml::array toArray(const py::list& list, const std::string& at);

void addToArray(toml::array& a, const py::handle& v, const std::string& at) {
  if (py::isinstance<py::bool_>(v))
    a.push_back(v.cast<bool>());
  else if (py::isinstance<py::int_>(v))
    a.push_back(v.cast<std::int64_t>());
  else if (py::isinstance<py::float_>(v) || py::hasattr(v, "__float__"))
    a.push_back(v.cast<double>());
  else if (py::isinstance<py::str>(v))
    a.push_back(v.cast<std::string>());
  else if (py::isinstance<py::dict>(v)) {
    toml::table sub;
    for (const auto& [k, x] : v.cast<py::dict>())
      insertValue(sub, py::str(k), x, at + "." + std::string(py::str(k)));
    a.push_back(std::move(sub));
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v))
    a.push_back(toArray(py::list(py::reinterpret_borrow<py::object>(v)), at));
  else
    throw InputError("study dict", 0, at,
                     "unsupported value type " + std::string(py::str(v.get_type())));
}

toml::array toArray(const py::list& list, const std::string& at) {
  toml::array a;
  for (std::size_t i = 0; i < list.size(); ++i)
    addToArray(a, list[i], at + "[" + std::to_string(i) + "]");
  return a;
}

void insertValue(toml::table& t, const std::string& key, const py::handle& v,
                 const std::string& at) {
  if (py::isinstance<py::dict>(v)) {
    toml::table sub;
    for (const auto& [k, x] : v.cast<py::dict>())
      insertValue(sub, py::str(k), x, at + "." + std::string(py::str(k)));
    t.insert(key, std::move(sub));
    return;
  }
  toml::array one;
  addToArray(one, v, at);
  t.insert(key, std::move(*one.get(0)));
}

// The dotted key path of the deepest node starting on `line` of the parsed text ("" if none).
void findLine(const toml::node& node, const std::string& at, int line, std::string& found) {
  if (static_cast<int>(node.source().begin.line) == line) found = at;
  if (const toml::table* t = node.as_table())
    for (const auto& [k, v] : *t)
      findLine(v, at.empty() ? std::string(k.str()) : at + "." + std::string(k.str()), line, found);
  else if (const toml::array* a = node.as_array())
    for (std::size_t i = 0; i < a->size(); ++i)
      findLine(*a->get(i), at + "[" + std::to_string(i) + "]", line, found);
}

RunOptions runOptions(const std::string& output, int threads, bool overwrite, long unit_size) {
  RunOptions o;
  o.output_root = output;
  o.threads = threads;
  o.overwrite = overwrite;
  o.unit_items = unit_size;
  o.progress = false;
  if (const std::string error = o.validate(); !error.empty()) throw std::invalid_argument(error);
  return o;
}

py::dict summaryDict(const Study& study, const RunSummary& sum) {
  py::dict out, timings, flags, maps;
  out["study"] = study.name;
  out["output_dir"] = sum.output_dir;
  out["designs"] = sum.designs;
  out["threads"] = sum.threads;
  out["files"] = sum.files_written;
  for (const auto& t : sum.timings) timings[py::str(t.stage)] = t.seconds;
  out["timings"] = timings;
  out["metrics"] = sum.metrics.scalars;
  for (const auto& [name, values] : sum.metrics.flags) {
    py::array_t<std::uint8_t> a(static_cast<py::ssize_t>(values.size()));
    std::copy(values.begin(), values.end(), a.mutable_data());
    flags[py::str(name)] = a;
  }
  out["flags"] = flags;
  for (const auto& f : sum.files_written)
    if (fs::path(f).extension() == ".vti") maps[py::str(f)] = readMap(sum.output_dir + "/" + f);
  out["maps"] = maps;
  return out;
}

py::dict run(const py::object& study, const std::string& output, int threads, bool overwrite,
             long unit_size, const std::string& folder) {
  const RunOptions options = runOptions(output, threads, overwrite, unit_size);
  if (!py::isinstance<py::dict>(study)) {
    const std::string path = study.cast<std::string>();
    const Study s = loadStudy(path);
    RunSummary sum;
    {
      py::gil_scoped_release release;
      sum = runStudy(s, options);
    }
    return summaryDict(s, sum);
  }
  toml::table root;
  for (const auto& [k, v] : study.cast<py::dict>()) insertValue(root, py::str(k), v, py::str(k));
  std::ostringstream text;
  text << root << "\n";
  const std::string label = "study dict";
  std::optional<Study> s;
  try {
    s.emplace(loadStudyText(text.str(), label, folder));
  } catch (const InputError& e) {
    if (e.file() != label || e.line() <= 0) throw;
    const toml::table parsed = io::parseTomlText(text.str(), label);
    std::string key;
    findLine(parsed, "", e.line(), key);
    throw InputError(label, 0, key.empty() ? e.key() : key, e.message());
  }
  RunSummary sum;
  {
    py::gil_scoped_release release;
    sum = runStudy(*s, options);
  }
  return summaryDict(*s, sum);
}

}  // namespace

void bindStudy(py::module_& m) {
  m.def("run_study", &run, py::arg("study"), py::arg("output") = "output", py::arg("threads") = 0,
        py::arg("overwrite") = false, py::arg("unit_size") = 0, py::arg("folder") = ".",
        R"(Runs a study as `armstudy run` does, writing the same files into output/<name>/.
study: a study file path, or a dict with the study file's tables (relative paths in it resolve
against `folder`; an error names the dict's key path, e.g. 'reach.grid[0].step').
Returns a dict: study, output_dir, designs, threads, files, timings, metrics (the summary
scalars), flags (per-pose uint8 arrays), maps ({file: read_map(file)} for every .vti written).)");
  m.def(
      "read_map", &readMap, py::arg("path"),
      R"(Reads a .vti map: dims, origin, spacing, axes {x, y, z}, arrays {name: (nz, ny, nx[, c])},
units, legend and names ({array: {value: meaning}}, e.g. the status names).)");
}

}  // namespace armstudy::python
