#include "calibration/calibration_run.hpp"

#include <filesystem>

#include "calibration/calibrated_design.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

drive::Effect parseDriveEffect(const std::string& name, const std::string& file, int line,
                               const std::string& key) {
  drive::Effect e;
  if (drive::parseEffect(name, e)) return e;
  std::string names;
  for (const drive::EffectDeclaration& d : drive::effectDeclarations())
    names += (names.empty() ? "" : ", ") + std::string(d.name);
  throw InputError(file, line, key, "unknown effect '" + name + "' (expected " + names + ")");
}

std::string noCalibratedDesign(const ArmDiagnosis& d) { return d.identifiable; }

ArmFitFiles writeArmFit(const ArmDiagnosis& d, const ArmProblem& P, const Model& m,
                        const std::string& out_dir, const std::string& design_path, bool lock,
                        const std::vector<std::pair<std::string, std::string>>& extra_files) {
  ArmFitFiles f;
  if (const std::string why = noCalibratedDesign(d); !why.empty()) {
    f.notes.push_back(why);
    f.report = writeArmReport(d, P, ArmReportOptions{out_dir, "fit", extra_files, lock}, "");
    return f;
  }
  const CalibratedDesign c = calibratedDesign(m, P, d.final_fit.values, f.notes);
  f.calibrated_design_path =
      design_path.empty() ? out_dir + "/" + c.model.name + ".toml" : design_path;
  if (!c.urdf.empty())
    f.calibrated_urdf_path =
        std::filesystem::path(f.calibrated_design_path).replace_extension(".urdf").string();
  ArmReportOptions o{out_dir, "fit", extra_files, lock};
  if (design_path.empty()) {  // in the output folder: published with the report as one folder
    o.extra_files.emplace_back(c.model.name + ".toml", c.toml);
    if (!c.urdf.empty()) o.extra_files.emplace_back(c.model.name + ".urdf", c.urdf);
  }
  f.report = writeArmReport(d, P, o, f.calibrated_design_path);
  if (!design_path.empty()) {
    writeFileAtomic(f.calibrated_design_path, c.toml);
    if (!c.urdf.empty()) writeFileAtomic(f.calibrated_urdf_path, c.urdf);
  }
  return f;
}

}  // namespace armstudy::calibration
