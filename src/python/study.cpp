// Studies: run one from a file or from a dict (the same runner as `armstudy run`, so the same
// files), and read the maps it wrote back as arrays with their grid axes.
#include <pybind11/eval.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <toml++/toml.h>
#include <vtkAbstractArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/toml_reader.hpp"
#include "python/bindings.hpp"
#include "study/stage.hpp"
#include "study/unit_runner.hpp"

namespace armstudy::python {

namespace fs = std::filesystem;

// Nested arrays and tables a study dict may hold: as many as the TOML reader lets a study file
// hold (toml++'s cap).
constexpr int kMaxNesting = TOML_MAX_NESTED_VALUES;
// Values a study dict may hold in all: far more than any study, and it ends a dict whose lists
// repeat one another (a list of the same list, 30 deep, would expand to 2^30 values).
constexpr long kMaxValues = 1000000;

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

// Collects a VTK object's error and warning messages instead of printing them.
class Messages : public vtkCommand {
 public:
  static Messages* New() { return new Messages; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (data && text.empty()) text = static_cast<const char*>(data);
    failed = true;
  }
  bool failed = false;
  std::string text;
};

// A point array as numpy values of its own kind: integer arrays (status, flags, counts) as
// integers of the same width and sign, floating arrays as float64.
template <class T>
py::array copyArray(vtkDataArray* data, const std::vector<py::ssize_t>& shape) {
  py::array_t<T> values(shape);
  T* v = values.mutable_data();
  const int c = data->GetNumberOfComponents();
  const vtkIdType n = data->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i)
    for (int k = 0; k < c; ++k) v[i * c + k] = static_cast<T>(data->GetComponent(i, k));
  return values;
}

py::array arrayValues(vtkDataArray* data, const std::vector<py::ssize_t>& shape) {
  switch (data->GetDataType()) {
    case VTK_UNSIGNED_CHAR:
      return copyArray<std::uint8_t>(data, shape);
    case VTK_SIGNED_CHAR:
    case VTK_CHAR:
      return copyArray<std::int8_t>(data, shape);
    case VTK_UNSIGNED_SHORT:
      return copyArray<std::uint16_t>(data, shape);
    case VTK_SHORT:
      return copyArray<std::int16_t>(data, shape);
    case VTK_UNSIGNED_INT:
      return copyArray<std::uint32_t>(data, shape);
    case VTK_INT:
      return copyArray<std::int32_t>(data, shape);
    case VTK_UNSIGNED_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      return copyArray<std::uint64_t>(data, shape);
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      return copyArray<std::int64_t>(data, shape);
    default:
      return copyArray<double>(data, shape);
  }
}

py::dict readMap(const std::string& path) {
  if (!fs::is_regular_file(path))
    throw InputError(path, 0, "", "no map file (expected a .vti file that armstudy run wrote)");
  vtkNew<vtkXMLImageDataReader> reader;
  vtkNew<Messages> messages;
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(path.c_str());
  if (!reader->CanReadFile(path.c_str()))
    throw InputError(path, 0, "", "not a VTK image data (.vti) file");
  {
    // VTK's other objects (its XML parser, the pipeline) print their errors: not here, they are
    // the InputError below.
    const int shown = vtkObject::GetGlobalWarningDisplay();
    vtkObject::GlobalWarningDisplayOff();
    reader->Update();
    vtkObject::SetGlobalWarningDisplay(shown);
  }
  if (messages->failed || !reader->GetOutput() || reader->GetOutput()->GetNumberOfPoints() == 0) {
    std::string why = messages->text;
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    if (const auto at = why.rfind(": "); at != std::string::npos && why.size() - at < 300)
      why = why.substr(at + 2);
    throw InputError(path, 0, "",
                     "not a readable VTK image data (.vti) file" + (why.empty() ? "" : ": " + why));
  }
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
    arrays[data->GetName()] = arrayValues(data, shape);
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

const char* const kDictLabel = "study dict";

[[noreturn]] void dictError(const std::string& at, const std::string& message) {
  throw InputError(kDictLabel, 0, at, message);
}

std::string typeName(const py::handle& v) {
  return py::str(py::type::of(v).attr("__name__")).cast<std::string>();
}

std::string shortRepr(const py::handle& v) {
  std::string r;
  try {
    r = py::repr(v).cast<std::string>();
  } catch (py::error_already_set&) {
    return "a " + typeName(v);
  }
  return r.size() > 40 ? r.substr(0, 37) + "..." : r;
}

std::string utf8(const py::handle& v, const std::string& at) {
  Py_ssize_t size = 0;
  const char* text = PyUnicode_AsUTF8AndSize(v.ptr(), &size);
  if (!text) {
    PyErr_Clear();
    dictError(at, "the string is not valid Unicode text (it holds a lone surrogate)");
  }
  return std::string(text, static_cast<std::size_t>(size));
}

// An integer (int, numpy integers: anything with __index__) in TOML's 64-bit range.
std::int64_t integer(const py::handle& v, const std::string& at) {
  const py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
  if (!i) throw py::error_already_set();
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow)
    dictError(at, "integer " + shortRepr(i) + " is beyond the 64-bit range a TOML integer holds");
  if (x == -1 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

double number(const py::handle& v) {
  const double x = PyFloat_AsDouble(v.ptr());
  if (x == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

toml::table toTable(const py::dict& d, const std::string& at, int depth, long& values);
toml::array toArray(const py::handle& sequence, const std::string& at, int depth, long& values);

// Converts one value of the dict at key path `at` (`depth` containers deep) and hands the TOML
// value to `add`; `values` counts the values converted. Nesting is capped like the TOML reader's
// (which also ends a dict that holds itself); a value TOML cannot hold is an input error naming the
// path.
template <class Add>
void convertValue(const py::handle& v, const std::string& at, int depth, long& values, Add&& add) {
  if (++values > kMaxValues)
    dictError(at, "the study dict holds more than " + std::to_string(kMaxValues) +
                      " values (do its lists repeat one another?)");
  if (depth > kMaxNesting)
    dictError(at, "nested deeper than " + std::to_string(kMaxNesting) +
                      " levels (does a dict or list contain itself?)");
  if (v.is_none()) dictError(at, "None is not a study value (leave the key out for its default)");
  // numpy scalars and arrays: their Python values (tolist: int, float, bool, nested lists).
  if (py::hasattr(v, "dtype") && py::hasattr(v, "tolist")) {
    py::object plain;
    try {
      plain = v.attr("tolist")();
    } catch (py::error_already_set& e) {
      dictError(at, shortRepr(v) + " could not be read: " + std::string(e.what()).substr(0, 200));
    }
    if (!py::hasattr(plain, "dtype")) {
      --values;
      convertValue(plain, at, depth, values, add);
      return;
    }
  }
  try {
    if (py::isinstance<py::bool_>(v))
      add(v.ptr() == Py_True);
    else if (py::isinstance<py::str>(v))
      add(utf8(v, at));
    else if (py::isinstance<py::dict>(v))
      add(toTable(py::reinterpret_borrow<py::dict>(v), at, depth + 1, values));
    else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v))
      add(toArray(v, at, depth + 1, values));
    else if (py::hasattr(v, "__index__"))
      add(integer(v, at));
    else if (py::hasattr(v, "__float__"))
      add(number(v));
    else
      dictError(at, "a value of type " + typeName(v) +
                        " is not a study value (numbers, strings, booleans, lists and dicts are)");
  } catch (py::error_already_set& e) {
    dictError(at, shortRepr(v) + " could not be read: " + std::string(e.what()).substr(0, 200));
  }
}

toml::table toTable(const py::dict& d, const std::string& at, int depth, long& values) {
  toml::table t;
  for (const auto& [k, v] : d) {
    if (!py::isinstance<py::str>(k))
      dictError(at, "key " + shortRepr(k) + " is not a string (study keys are)");
    const std::string key = utf8(k, at);
    const std::string path = at.empty() ? key : at + "." + key;
    convertValue(v, path, depth, values,
                 [&](auto&& x) { t.insert(key, std::forward<decltype(x)>(x)); });
  }
  return t;
}

toml::array toArray(const py::handle& sequence, const std::string& at, int depth, long& values) {
  toml::array a;
  const py::sequence items = py::reinterpret_borrow<py::sequence>(sequence);
  for (std::size_t i = 0; i < items.size(); ++i)
    convertValue(items[i], at + "[" + std::to_string(i) + "]", depth, values,
                 [&](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
  return a;
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

// A study dict read as the study file it stands for: its TOML text through the study reader, with
// a message's line turned into the dict's key path.
Study studyFromDict(const py::dict& study, const std::string& folder) {
  std::ostringstream text;
  long values = 0;
  text << toTable(study, "", 0, values) << "\n";
  try {
    return loadStudyText(text.str(), kDictLabel, folder);
  } catch (const InputError& e) {
    if (e.file() != kDictLabel || e.line() <= 0) throw;
    const toml::table parsed = io::parseTomlText(text.str(), kDictLabel);
    std::string key;
    findLine(parsed, "", e.line(), key);
    // The reader's own key when it names the found entry or a key inside it (a missing
    // 'reach.grid[0].x.step' is on the line of 'reach.grid[0].x').
    const bool inside = e.key().rfind(key, 0) == 0;
    throw InputError(kDictLabel, 0, key.empty() || inside ? e.key() : key, e.message());
  }
}

// `study`: a study file path (str or os.PathLike) or a dict with the study file's tables.
Study readStudy(const py::object& study, const std::string& folder) {
  if (py::isinstance<py::dict>(study)) return studyFromDict(study, folder);
  const py::object path = pathLike(study);
  if (!py::isinstance<py::str>(path))
    throw InputError(
        "arguments", 0, "study",
        "expected a study file path or a dict, got a value of type " + typeName(study));
  return loadStudy(utf8(path, "study"));
}

RunOptions runOptions(const std::string& output, int threads, bool overwrite, long unit_size,
                      int preview) {
  checkArgument("threads", threads, 0, defaults::kMaxThreads, " (0 = all cores)");
  checkArgument("unit_size", unit_size, 0, defaults::kMaxUnitItems, " (0 = each stage's default)");
  checkArgument("preview", preview, 0, defaults::kMaxPreviewStride, " (0 = none)");
  RunOptions o;
  o.output_root = output;
  o.threads = forkedChild() ? 1 : threads;  // bindings.hpp: one thread after a fork
  o.overwrite = overwrite;
  o.unit_items = unit_size;
  o.preview_stride = preview;
  o.progress = false;
  if (const std::string error = o.validate(); !error.empty())
    throw InputError("arguments", 0, "output", error);
  return o;
}

py::dict summaryDict(const Study& study, const RunSummary& sum) {
  py::dict out, timings, flags, maps;
  out["study"] = study.name;
  out["output_dir"] = sum.output_dir;
  out["designs"] = sum.designs;
  out["threads"] = sum.threads;
  out["files"] = sum.files_written;
  out["units_resumed"] = sum.units_resumed;
  out["resume_message"] = sum.resume_message;
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

py::dict run(const py::object& study, const fs::path& output, int threads, bool overwrite,
             long unit_size, const fs::path& folder, int preview, const py::object& on_preview) {
  RunOptions options = runOptions(output.string(), threads, overwrite, unit_size, preview);
  if (!on_preview.is_none() && !PyCallable_Check(on_preview.ptr()))
    throw InputError("arguments", 0, "on_preview",
                     "expected a callable or None, got a value of type " + typeName(on_preview));
  const Study s = readStudy(study, folder.string());
  // Ctrl-C: between slices of units the runner asks for the GIL and runs Python's signal handlers;
  // their exception (KeyboardInterrupt) stops the run with the completed units saved. An exception
  // of on_preview (called on the thread that wrote the preview) stops it the same way.
  std::optional<py::error_already_set> interrupt;
  std::mutex interrupt_mutex;
  options.cancelled = [&] {
    py::gil_scoped_acquire gil;
    const std::lock_guard<std::mutex> lock(interrupt_mutex);
    if (interrupt) return true;
    if (PyErr_CheckSignals() == 0) return false;
    interrupt.emplace();
    return true;
  };
  if (!on_preview.is_none())
    options.on_preview = [&](const std::string& file) {
      py::gil_scoped_acquire gil;
      try {
        on_preview(file);
      } catch (py::error_already_set& e) {
        const std::lock_guard<std::mutex> lock(interrupt_mutex);
        if (!interrupt) interrupt.emplace(std::move(e));
      }
    };
  RunSummary sum;
  try {
    py::gil_scoped_release release;
    sum = runStudy(s, options);
  } catch (const RunCancelled&) {
    if (interrupt) throw *interrupt;
    throw;
  }
  if (interrupt) throw *interrupt;  // on_preview failed after the last check
  return py::module_::import("armstudy").attr("StudyResult")(summaryDict(s, sum));
}

// What a study holds once read and validated (check_study): nothing is run or written.
py::dict check(const py::object& study, const fs::path& folder) {
  const Study s = readStudy(study, folder.string());
  py::dict out;
  py::list designs, stages, inputs;
  for (const StudyDesign& d : s.designs) designs.append(d.model.name);
  for (const StudySection& section : s.sections) stages.append(section.stage->name());
  for (const InputFile& f : s.inputs) inputs.append(f.path);
  out["study"] = s.name;
  out["description"] = s.description;
  out["designs"] = designs;
  out["stages"] = stages;
  out["inputs"] = inputs;
  return out;
}

}  // namespace

// The dict run_study returns, with its notebook display (Jupyter calls _repr_html_).
const char* const kStudyResult = R"PY(
import base64 as _base64, html as _html, os as _os, re as _re

class StudyResult(dict):
    """What run_study returns: a dict (study, output_dir, designs, threads, files, units_resumed,
    resume_message, timings, metrics, flags, maps). In Jupyter it shows as the report does: the
    study's answer block (report.md's Answer, Warnings and Assumptions) and its first map image."""

    _ANSWER_SECTIONS = ("## Answer\n", "## Warnings\n", "## Assumptions\n")

    def answer(self):
        """The answer block of the study's report.md (Markdown; '' if none): its Answer and
        Warnings sections and, when the results rest on assumed values, its Assumptions."""
        try:
            with open(_os.path.join(self["output_dir"], "report.md"), encoding="utf-8") as f:
                text = f.read()
        except OSError:
            return ""
        start = text.find("## Answer\n")
        if start < 0:
            return ""
        end = start
        while True:  # up to the first heading of level 2 that is not of the block
            end = text.find("\n## ", end + 1)
            if end < 0 or not text.startswith(self._ANSWER_SECTIONS, end + 1):
                break
        return text[start:] if end < 0 else text[start:end]

    def first_map(self):
        """Path of the first map image (PNG) the study wrote, or None."""
        for f in self.get("files", []):
            name = _os.path.basename(f)
            if f.endswith(".png") and not name.startswith("arm_"):
                return _os.path.join(self["output_dir"], f)
        return None

    def _repr_html_(self):
        def inline(t):
            t = _html.escape(t)
            t = _re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", t)
            return _re.sub(r"`(.+?)`", r"<code>\1</code>", t)
        out = [f"<h3>Study <code>{_html.escape(str(self.get('study', '')))}</code></h3>",
               f"<p>{_html.escape(str(self.get('output_dir', '')))}</p>"]
        items = False
        for line in self.answer().splitlines():
            if line.startswith("## "):
                if items:
                    out.append("</ul>")
                    items = False
                out.append(f"<h4>{inline(line[3:])}</h4>")
            elif line.startswith("- "):
                if not items:
                    out.append("<ul>")
                    items = True
                out.append(f"<li>{inline(line[2:])}</li>")
            elif line.strip():
                out.append(f"<p>{inline(line)}</p>")
        if items:
            out.append("</ul>")
        image = self.first_map()
        if image:
            with open(image, "rb") as f:
                data = _base64.b64encode(f.read()).decode("ascii")
            out.append(f'<figure><img src="data:image/png;base64,{data}"/>'
                       f"<figcaption>{_html.escape(_os.path.relpath(image, self['output_dir']))}"
                       "</figcaption></figure>")
        return "\n".join(out)

StudyResult.__module__ = "armstudy"
)PY";

void bindStudy(py::module_& m) {
  py::dict scope;
  scope["__builtins__"] = py::module_::import("builtins");
  py::exec(kStudyResult, scope);
  m.attr("StudyResult") = scope["StudyResult"];
  m.def("run_study", &run, py::arg("study"), py::arg("output") = "output", py::arg("threads") = 0,
        py::arg("overwrite") = false, py::arg("unit_size") = 0, py::arg("folder") = ".",
        py::arg("preview") = 0, py::arg("on_preview") = py::none(),
        R"(Runs a study as `armstudy run` does, writing the same files into output/<name>/.
study: a study file path, or a dict with the study file's tables (relative paths in it resolve
against `folder`; an error names the dict's key path, e.g. 'reach.grid[0].step'). threads and
unit_size have the CLI's bounds (0..256, 0..1e9); beyond them InputError names the argument.
Returns a StudyResult (a dict that Jupyter shows as the report's answer block and first map):
study, output_dir, designs, threads, files, units_resumed and resume_message (what a resumed run
loaded), timings, metrics (the summary scalars), flags (per-pose uint8 arrays), maps
({file: read_map(file)} for every .vti written). output and folder: str or os.PathLike.
Ctrl-C (KeyboardInterrupt) stops the run between work units, within about a second; the units
done are saved, so the same call again resumes, as after the CLI's Ctrl-C.
preview=K (0..100, as `armstudy run --preview K`): before the stem maps and reach grids are
computed, each design's map on every K-th value along each axis is written to dexterity/preview/ or
reach/preview/ (.svg and .png), and on_preview(path) is called with the .png's path as soon as it
exists (e.g. to show it in a notebook); an exception it raises stops the run as Ctrl-C does and is
raised again. The other files do not depend on it.)");
  m.def("check_study", &check, py::arg("study"), py::arg("folder") = ".",
        R"(Reads and validates a study (a file path or a dict, as run_study) without running it:
the designs and data it names are loaded and checked, nothing is written. Returns a dict: study,
description, designs (names, variants included), stages (the sections present), inputs (files
read). Raises InputError as run_study would.)");
  m.def(
      "read_map", [](const fs::path& path) { return readMap(path.string()); }, py::arg("path"),
      R"(Reads a .vti map: dims, origin, spacing, axes {x, y, z}, arrays {name: (nz, ny, nx[, c])},
units, legend and names ({array: {value: meaning}}, e.g. the status names). Integer arrays
(status, flags, counts) keep their integer type; the others are float64. path: str or
os.PathLike. Raises InputError (file = path) when the file is missing or not a .vti image.)");
}

}  // namespace armstudy::python
