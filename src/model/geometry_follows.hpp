#pragma once
// Geometry that follows (docs/exploration.md, "Geometry that follows"): when a variant changes
// where a link ends (the x, y, z of the next joint's table row, or of the TCP offset for the last
// link), the collision volumes and the inertial data attached to that link are adapted to the new
// length instead of being kept from the base design.
//
// Rule, per link i whose end moved from a_old to a_new (both in frame i), applied to every core
// point p of every volume attached to link i and to the link's centre of mass, axis k by axis k:
//   - |a_old[k]| > 0: piecewise linear along that axis. With u = p[k] / a_old[k]:
//       u <= 0 (behind the link origin): unchanged; 0 < u < 1 (along the link): scaled,
//       p[k] * a_new[k] / a_old[k]; u >= 1 (at or beyond the link end, e.g. the next joint's
//       housing): shifted rigidly with the end, p[k] + (a_new[k] - a_old[k]).
//   - a_old[k] == 0 (the link gains an offset along a new axis): shifted by t * (a_new[k] -
//     a_old[k]) with t the position of p along the old link, clamp(p . a_old / |a_old|^2, 0, 1).
// The link origin stays, the old link end maps onto the new one exactly, so a volume spanning the
// link (a capsule from the origin to the end, a triangle over an L-shaped offset) spans the new
// link. Radii are kept. A link of zero old length cannot be stretched: its volumes are kept and
// the note says so. Inertias: the mass is kept (an assumption: the added or removed tube mass is
// not known), the COM maps by the rule above, and the mass distribution about the COM is stretched
// by S = diag(a_new[k] / a_old[k]) (1 on axes of zero old length): Sigma' = S Sigma S with
// Sigma = tr(I)/2 E - I, I' = tr(Sigma') E - Sigma'. Everything adapted is listed in the notes.
#include <string>
#include <vector>

#include "model/model.hpp"

namespace armstudy {

// Adapts `variant` (a copy of `base` with table entries overridden) by the rule above and returns
// one note per adapted (or not adaptable) link; the notes are also appended to
// variant.assumptions. Both models have the same joints in the same order.
std::vector<std::string> followLinkGeometry(const Model& base, Model& variant);

// The map of the rule above for one link end moving from a_old to a_new (exposed for tests).
Eigen::Vector3d stretchPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& a_old,
                             const Eigen::Vector3d& a_new);

}  // namespace armstudy
