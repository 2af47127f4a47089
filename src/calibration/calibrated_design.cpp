// The calibrated design writer (calibrated_design.hpp) and shownDesign (arm_calibration.hpp).
#include "calibration/calibrated_design.hpp"

#include <sstream>

#include "common/errors.hpp"
#include "common/join.hpp"
#include "io/design_io.hpp"
#include "io/urdf_io.hpp"

namespace armstudy::calibration {

namespace {

// The values of `b` that differ from `a` and that exportUrdf does not write (drives, model
// effects, joint armature and effort offsets), one phrase each.
std::vector<std::string> notInUrdf(const Model& a, const Model& b) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < b.drives.size() && i < a.drives.size(); ++i) {
    const Drive &x = a.drives[i], &y = b.drives[i];
    if (x.friction_law != y.friction_law || x.friction != y.friction)
      out.push_back("the friction of drive " + y.joint + " ([drive.friction])");
    if (x.rotor_inertia_kgm2 != y.rotor_inertia_kgm2)
      out.push_back("the rotor inertia of drive " + y.joint);
  }
  if (a.effects != b.effects) out.push_back("the [model] effects");
  for (int j = 0; j < b.dof(); ++j) {
    const JointDynamics &x = a.joints[j].dynamics, &y = b.joints[j].dynamics;
    if (x.armature != y.armature) out.push_back("the armature of " + b.joints[j].name);
    if (x.effort_offset != y.effort_offset)
      out.push_back("the effort offset of " + b.joints[j].name);
  }
  return out;
}

bool samePose(const PoseXYZABG& a, const PoseXYZABG& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z && a.alpha == b.alpha && a.beta == b.beta &&
         a.gamma == b.gamma;
}

// The six entries the design format holds (xx yy zz xy xz yz; a lumped URDF body's tensor may be
// symmetric only to rounding, the file's is symmetric).
bool sameInertia(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return a(0, 0) == b(0, 0) && a(1, 1) == b(1, 1) && a(2, 2) == b(2, 2) && a(0, 1) == b(0, 1) &&
         a(0, 2) == b(0, 2) && a(1, 2) == b(1, 2);
}

// The calibrated TOML read back must be the calibrated Model (designToToml writes every value at
// round-trip precision).
void checkReadBack(const Model& cal, const std::string& toml) {
  const Model back = parseDesign(toml, cal.name + ".toml");
  bool same = back.dof() == cal.dof() && back.payload_kg == cal.payload_kg &&
              back.p_payload_com_T == cal.p_payload_com_T && back.effects == cal.effects &&
              samePose(back.base, cal.base) && back.drives.size() == cal.drives.size() &&
              back.inertias.size() == cal.inertias.size();
  for (int j = 0; same && j < cal.dof(); ++j) {
    const JointDynamics &x = back.joints[j].dynamics, &y = cal.joints[j].dynamics;
    same = samePose(back.joints[j].offset, cal.joints[j].offset) && x.coulomb == y.coulomb &&
           x.viscous == y.viscous && x.armature == y.armature && x.effort_offset == y.effort_offset;
  }
  for (std::size_t i = 0; same && i < cal.drives.size(); ++i)
    same = back.drives[i].friction == cal.drives[i].friction &&
           back.drives[i].friction_law == cal.drives[i].friction_law &&
           back.drives[i].rotor_inertia_kgm2 == cal.drives[i].rotor_inertia_kgm2;
  for (std::size_t i = 0; same && i < cal.inertias.size(); ++i)
    same = back.inertias[i].mass_kg == cal.inertias[i].mass_kg &&
           sameInertia(back.inertias[i].I_com_kgm2, cal.inertias[i].I_com_kgm2);
  ARMSTUDY_CHECK(same, "the calibrated design TOML reads back as the calibrated Model");
}

}  // namespace

bool isUrdfDesign(const Model& design) { return isUrdfPath(design.file); }

CalibratedDesign calibratedDesign(const Model& design, const ArmProblem& problem,
                                  const EffectValues& values, std::vector<std::string>& notes) {
  CalibratedDesign c;
  const std::size_t kind_notes = notes.size();
  c.model = problem.calibratedModel(design, values, notes);
  c.model.name = design.name + "_calibrated";
  std::ostringstream head;
  head << kCalibratedDesignHeader << design.name << "' (" << design.file
       << "): the fitted values of armstudy fit (result.json) applied to its model.\n";
  for (std::size_t i = kind_notes; i < notes.size(); ++i) head << "# " << notes[i] << "\n";
  c.toml = head.str() + designToToml(c.model);
  checkReadBack(c.model, c.toml);
  if (!isUrdfDesign(design)) return c;
  c.urdf_cannot_hold = notInUrdf(design, c.model);
  std::string comment =
      "Calibrated copy of design '" + design.name +
      "' (armstudy fit): each joint's <dynamics> holds its fitted joint-side friction (damping = "
      "viscous, friction = Coulomb level).";
  if (!c.urdf_cannot_hold.empty()) {
    comment += " URDF cannot hold " + join(c.urdf_cannot_hold, ", ") + "; " + c.model.name +
               ".toml holds all fitted values.";
    notes.push_back("the calibrated URDF cannot hold " + join(c.urdf_cannot_hold, ", ") +
                    "; the calibrated TOML holds them");
  }
  std::string urdf = exportUrdf(c.model);
  const auto eol = urdf.find('\n');
  c.urdf = urdf.substr(0, eol + 1) + "<!-- " + comment + " -->\n" + urdf.substr(eol + 1);
  return c;
}

ShownDesign shownDesign(const std::string& text) {
  return text.rfind(kCalibratedDesignHeader, 0) == 0 ? ShownDesign::calibrated_copy
                                                     : ShownDesign::as_designed;
}

}  // namespace armstudy::calibration
