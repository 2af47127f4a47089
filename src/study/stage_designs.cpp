#include "study/stage_designs.hpp"

#include <algorithm>

#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/toml_reader.hpp"
#include "model/model_notes.hpp"

namespace armstudy {

namespace {

std::string namesOf(const std::vector<const Model*>& models) {
  std::string names;
  for (const Model* m : models) names += (names.empty() ? "" : ", ") + m->name;
  return names;
}

bool named(const std::vector<const Model*>& models, const std::string& name) {
  return std::find_if(models.begin(), models.end(),
                      [&](const Model* m) { return m->name == name; }) != models.end();
}

}  // namespace

std::vector<const Model*> StageDesigns::evaluated(const std::vector<const Model*>& models) const {
  if (names.empty()) return models;
  std::vector<const Model*> out;
  for (const Model* m : models)
    if (std::find(names.begin(), names.end(), m->name) != names.end()) out.push_back(m);
  return out;
}

Study StageDesigns::select(const Study& study) const {
  Study s = study;
  if (!names.empty())
    s.designs.erase(std::remove_if(s.designs.begin(), s.designs.end(),
                                   [&](const StudyDesign& sd) {
                                     return std::find(names.begin(), names.end(), sd.model.name) ==
                                            names.end();
                                   }),
                    s.designs.end());
  for (StudyDesign& sd : s.designs)
    for (const auto& [name, axis] : tool_axes)
      if (sd.model.name == name) {
        sd.model.tool_axis_T = axis;
        notes::toolAxisNamed(sd.model, "the stage's tool_axis table");
      }
  return s;
}

StageDesigns readStageDesigns(io::TableReader& r, const std::string& file,
                              const std::vector<const Model*>& models) {
  StageDesigns d;
  if (r.has("designs")) {
    d.names = r.stringArray("designs");
    if (d.names.empty()) r.fail("designs", "empty list of designs");
    for (const auto& n : d.names)
      if (!named(models, n))
        r.fail("designs",
               "design '" + n + "' is not part of the study (designs: " + namesOf(models) + ")");
  }
  const std::vector<const Model*> evaluated = d.evaluated(models);
  if (const toml::table* ta = r.table("tool_axis")) {
    io::TableReader tr(*ta, file, r.keyPath("tool_axis"));
    for (auto&& [key, value] : *ta) {
      const std::string name(key.str());
      if (!named(evaluated, name))
        tr.fail(name, "design '" + name +
                          "' is not evaluated by this stage (designs: " + namesOf(evaluated) + ")");
      d.tool_axes.emplace_back(name, readToolAxis(tr, name, Eigen::Vector3d::UnitZ()));
    }
    tr.finish();
  }
  return d;
}

}  // namespace armstudy
