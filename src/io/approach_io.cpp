#include "io/approach_io.hpp"

#include "io/toml_reader.hpp"

namespace armstudy {

ApproachPlannerOptions readApproachOptions(io::TableReader& r) {
  ApproachPlannerOptions o;
  o.entry_radius_m = r.quantity("entry_radius", Dimension::Length, o.entry_radius_m);
  if (!(o.entry_radius_m > 0)) r.fail("entry_radius", "entry radius r_e must be positive");
  o.s_a = r.number("s_a", o.s_a);
  o.s_e = r.number("s_e", o.s_e);
  if (!(o.s_e > 0 && o.s_e < 1)) r.fail("s_e", "s_e must lie in (0, 1) (thesis eq. 5.16b)");
  if (!(o.s_a >= 0 && o.s_a < o.s_e)) r.fail("s_a", "s_a must lie in [0, s_e) (thesis eq. 5.18)");
  o.duration_s = r.number("duration");
  if (!(o.duration_s > 0)) r.fail("duration", "trajectory duration must be positive (seconds)");
  o.exp_scale_m = r.quantity("exp_scale", Dimension::Length, o.exp_scale_m);
  if (!(o.exp_scale_m > 0)) r.fail("exp_scale", "exponential length scale must be positive");
  o.alpha_goal_rad = r.quantity("alpha_goal", Dimension::Angle, o.alpha_goal_rad);
  o.beta_goal_rad = r.quantity("beta_goal", Dimension::Angle, o.beta_goal_rad);
  o.gamma_offset_rad = r.quantity("gamma_offset", Dimension::Angle, o.gamma_offset_rad);
  std::string err;
  ARMSTUDY_CHECK(o.validate(err),
                 "approach reader and ApproachPlannerOptions::validate disagree: " + err);
  return o;
}

ApproachPlannerOptions parseApproachOptions(const std::string& text, const std::string& file) {
  const toml::table root = io::parseTomlText(text, file);
  io::TableReader top(root, file, "");
  const toml::table* t = top.table("approach");
  if (!t) throw InputError(file, 1, "approach", "missing table [approach]");
  io::TableReader r(*t, file, "approach");
  const ApproachPlannerOptions o = readApproachOptions(r);
  r.finish();
  top.finish();
  return o;
}

}  // namespace armstudy
