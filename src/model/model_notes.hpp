#pragma once
// Facts about a design that its importer knows and a run must say, kept as lines of
// Model::assumptions with a fixed opening (so they travel wherever the assumptions go: a design
// TOML written by `convert`, designs.json, describe):
//   "tool axis: ..."                       where Model::tool_axis_T comes from
//   "tool axis open: ..."                  the design leaves its tool axis open (a URDF arm whose
//                                          TCP is off its last joint's axis): the candidates and
//                                          the keys that name one; tool-axis stages refuse it
//   "no collision volume on link ..."      a link self-collision does not cover, with why
//   "mass lumped: ..."                     a link off the chain whose mass rides on a chain link
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace armstudy::notes {

inline constexpr const char* kToolAxisFrom = "tool axis: ";
inline constexpr const char* kToolAxisOpen = "tool axis open: ";
inline constexpr const char* kNoCollision = "no collision volume on link ";
inline constexpr const char* kLumped = "mass lumped: ";

inline bool opens(const std::string& line, const std::string& prefix) {
  return line.compare(0, prefix.size(), prefix) == 0;
}

// The notes of `m` with `prefix`, without it.
inline std::vector<std::string> all(const Model& m, const std::string& prefix) {
  std::vector<std::string> out;
  for (const std::string& a : m.assumptions)
    if (opens(a, prefix)) out.push_back(a.substr(prefix.size()));
  return out;
}

// The last note with `prefix` ("" when none).
inline std::string last(const Model& m, const std::string& prefix) {
  const std::vector<std::string> v = all(m, prefix);
  return v.empty() ? std::string() : v.back();
}

inline void add(Model& m, const std::string& prefix, const std::string& text) {
  m.assumptions.push_back(prefix + text);
}

// Replaces every note with `prefix` by `text` (none when `text` is empty).
inline void set(Model& m, const std::string& prefix, const std::string& text) {
  std::vector<std::string> kept;
  for (const std::string& a : m.assumptions)
    if (!opens(a, prefix)) kept.push_back(a);
  m.assumptions = kept;
  if (!text.empty()) add(m, prefix, text);
}

// The author's assumptions in `m` about `topic`: the lines that name it, case aside (a design's
// assumption line names what it is about: "Joint limits are not given ...", "... max_motor_speed
// 3500 rpm ... (assumption)"). A result limited by that quantity rests on these lines.
inline std::vector<std::string> about(const Model& m, const std::string& topic) {
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
  };
  std::vector<std::string> out;
  const std::string t = lower(topic);
  for (const std::string& a : m.assumptions)
    if (lower(a).find(t) != std::string::npos) out.push_back(a);
  return out;
}

// The topics of the limits a design states (the words its assumption lines use for them).
inline constexpr const char* kJointLimits = "joint limits";
inline constexpr const char* kVelocityLimits = "velocity limits";

// Where the tool axis comes from (a design TOML says nothing: its [tcp] tool_axis, else z).
inline std::string toolAxisFrom(const Model& m) {
  const std::string f = last(m, kToolAxisFrom);
  return f.empty() ? "the design file's [tcp] tool_axis (z when it names none)" : f;
}
inline std::string toolAxisOpen(const Model& m) { return last(m, kToolAxisOpen); }
// The tool axis named (by a design file, a study entry or a stage): it is no longer open.
inline void toolAxisNamed(Model& m, const std::string& from) {
  set(m, kToolAxisFrom, from);
  set(m, kToolAxisOpen, "");
}

}  // namespace armstudy::notes
