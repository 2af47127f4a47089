#include "model/geometry_follows.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"

namespace armstudy {

namespace {

// Link-end coordinates closer than this to zero count as "no length along that axis" [m].
constexpr double kZeroLength_m = 1e-12;

Eigen::Vector3d xyz(const PoseXYZABG& p) { return {p.x, p.y, p.z}; }

std::string vecText(const Eigen::Vector3d& v) {
  return "(" + formatG(v.x(), 6) + ", " + formatG(v.y(), 6) + ", " + formatG(v.z(), 6) + ") m";
}

// Rule of geometry_follows.hpp for the inertia about the COM (axis scales s).
Eigen::Matrix3d stretchInertia(const Eigen::Matrix3d& I, const Eigen::Vector3d& s) {
  const Eigen::Matrix3d E = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Sigma = 0.5 * I.trace() * E - I;  // second moment of the mass about the COM
  const Eigen::Matrix3d S = s.asDiagonal();
  const Eigen::Matrix3d Sigma_new = S * Sigma * S;
  return Sigma_new.trace() * E - Sigma_new;
}

}  // namespace

Eigen::Vector3d stretchPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& a_old,
                             const Eigen::Vector3d& a_new) {
  const double len2 = a_old.squaredNorm();
  const double t = len2 > 0 ? std::clamp(p.dot(a_old) / len2, 0.0, 1.0) : 0.0;
  Eigen::Vector3d out = p;
  for (int k = 0; k < 3; ++k) {
    const double d = a_new[k] - a_old[k];
    if (std::abs(a_old[k]) > kZeroLength_m) {
      const double u = p[k] / a_old[k];
      if (u >= 1)
        out[k] = p[k] + d;
      else if (u > 0)
        out[k] = p[k] * a_new[k] / a_old[k];
    } else {
      out[k] = p[k] + t * d;
    }
  }
  return out;
}

std::vector<std::string> followLinkGeometry(const Model& base, Model& variant) {
  std::vector<std::string> notes;
  const int n = variant.dof();
  // Link i (-1 = base) ends at joint i+1's origin, the last link at the TCP.
  for (int link = -1; link < n; ++link) {
    const Eigen::Vector3d a_old = link + 1 < n ? xyz(base.joints[link + 1].offset) : xyz(base.tcp);
    const Eigen::Vector3d a_new =
        link + 1 < n ? xyz(variant.joints[link + 1].offset) : xyz(variant.tcp);
    if (a_old == a_new) continue;
    const std::string body = link < 0 ? "base" : variant.joints[link].name;
    const std::string end = link + 1 < n ? "joint " + variant.joints[link + 1].name : "the TCP";
    std::string note = "Geometry follows: link " + body + " ends at " + end + " moved from " +
                       vecText(a_old) + " to " + vecText(a_new) + ";";
    int moved = 0;
    if (a_old.squaredNorm() <= kZeroLength_m * kZeroLength_m) {
      for (const CollisionVolume& v : variant.collision.volumes) moved += v.link == link;
      if (moved)
        note += " its " + std::to_string(moved) +
                " collision volume(s) are kept (a link of zero length cannot be stretched);";
    } else {
      for (CollisionVolume& v : variant.collision.volumes) {
        if (v.link != link) continue;
        for (int c = 0; c < static_cast<int>(v.type); ++c)
          v.p_L[c] = stretchPoint(v.p_L[c], a_old, a_new);
        ++moved;
      }
      if (moved) note += " " + std::to_string(moved) + " collision volume(s) stretched;";
    }
    if (link >= 0 && link < static_cast<int>(variant.inertias.size()) &&
        variant.inertias[link].given) {
      LinkInertia& in = variant.inertias[link];
      Eigen::Vector3d s = Eigen::Vector3d::Ones();
      for (int k = 0; k < 3; ++k)
        if (std::abs(a_old[k]) > kZeroLength_m) s[k] = a_new[k] / a_old[k];
      if (a_old.squaredNorm() > kZeroLength_m * kZeroLength_m)
        in.p_com_m = stretchPoint(in.p_com_m, a_old, a_new);
      in.I_com_kgm2 = stretchInertia(in.I_com_kgm2, s);
      note += " inertia re-estimated (COM moved, mass distribution stretched; mass kept at " +
              std::to_string(in.mass_kg).substr(0, 6) + " kg, an assumption);";
    }
    if (note.back() == ';') note.back() = '.';
    notes.push_back(note);
  }
  for (const auto& s : notes) variant.assumptions.push_back(s);
  return notes;
}

}  // namespace armstudy
