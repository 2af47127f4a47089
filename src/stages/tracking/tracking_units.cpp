#include <cstdint>

#include "stages/tracking/tracking_stage.hpp"
#include "study/checkpoint.hpp"

namespace armstudy::tracking {

namespace {

constexpr char kRunMagic[] = "armstudy-tracking-run-v1";

void putSample(UnitWriter& w, const RunSample& s) {
  w.put<double>(s.t);
  w.putMatrix(s.q);
  w.putMatrix(s.p_WT);
  w.put<double>(s.position_error_m);
  w.put<double>(s.orientation_error_rad);
  w.put<double>(s.obstacle_distance_m);
  w.put<double>(s.self_distance_m);
  w.put<std::int32_t>(s.obstacle_pair);
  w.put<std::int32_t>(s.self_pair);
}

void getSample(UnitReader& r, RunSample& s) {
  s.t = r.get<double>();
  r.getMatrix(s.q);
  r.getMatrix(s.p_WT);
  s.position_error_m = r.get<double>();
  s.orientation_error_rad = r.get<double>();
  s.obstacle_distance_m = r.get<double>();
  s.self_distance_m = r.get<double>();
  s.obstacle_pair = r.get<std::int32_t>();
  s.self_pair = r.get<std::int32_t>();
}

}  // namespace

std::string serializeRun(const RunResult& run) {
  UnitWriter w(kRunMagic);
  w.put<std::int32_t>(static_cast<std::int32_t>(run.kind));
  w.put<std::int32_t>(static_cast<std::int32_t>(run.status));
  w.put<std::int32_t>(run.limit_joint);
  w.put<std::uint64_t>(run.samples.size());
  for (const RunSample& s : run.samples) putSample(w, s);
  w.put<std::uint64_t>(run.pair_names.size());
  for (const std::string& n : run.pair_names) w.putString(n);
  w.put<double>(run.max_joint_speed);
  w.put<double>(run.max_speed_ratio);
  w.put<std::int32_t>(run.max_speed_joint);
  w.put<double>(run.min_obstacle_distance_m);
  w.put<double>(run.min_obstacle_time_s);
  w.put<std::int32_t>(run.min_obstacle_pair);
  w.put<double>(run.min_self_distance_m);
  w.put<double>(run.min_self_time_s);
  w.put<std::int32_t>(run.min_self_pair);
  w.put<double>(run.max_position_error_m);
  w.put<double>(run.max_orientation_error_rad);
  w.put<double>(run.final_position_error_m);
  w.put<std::uint8_t>(run.first_contact_s.has_value());
  w.put<double>(run.first_contact_s.value_or(0.0));
  w.put<std::int32_t>(run.first_contact_pair);
  return w.bytes();
}

bool deserializeRun(const std::string& bytes, RunResult& run) {
  UnitReader r(bytes, kRunMagic);
  RunResult x;
  x.kind = static_cast<RunKind>(r.get<std::int32_t>());
  x.status = static_cast<ik::TrackingStatus>(r.get<std::int32_t>());
  x.limit_joint = r.get<std::int32_t>();
  const auto n = r.get<std::uint64_t>();
  if (!r.ok() || n > bytes.size()) return false;  // each sample takes far more than one byte
  x.samples.resize(n);
  for (RunSample& s : x.samples) getSample(r, s);
  const auto np = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; r.ok() && k < np; ++k) x.pair_names.push_back(r.getString());
  x.max_joint_speed = r.get<double>();
  x.max_speed_ratio = r.get<double>();
  x.max_speed_joint = r.get<std::int32_t>();
  x.min_obstacle_distance_m = r.get<double>();
  x.min_obstacle_time_s = r.get<double>();
  x.min_obstacle_pair = r.get<std::int32_t>();
  x.min_self_distance_m = r.get<double>();
  x.min_self_time_s = r.get<double>();
  x.min_self_pair = r.get<std::int32_t>();
  x.max_position_error_m = r.get<double>();
  x.max_orientation_error_rad = r.get<double>();
  x.final_position_error_m = r.get<double>();
  const bool contact = r.get<std::uint8_t>() != 0;
  const double t_contact = r.get<double>();
  if (contact) x.first_contact_s = t_contact;
  x.first_contact_pair = r.get<std::int32_t>();
  if (!r.finished()) return false;
  run = std::move(x);
  return true;
}

}  // namespace armstudy::tracking
