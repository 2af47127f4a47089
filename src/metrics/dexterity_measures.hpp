#pragma once
// Dexterity measures of a Jacobian (thesis section 3.2.1 and 5.4.3): Yoshikawa manipulability
// (eq. 5.59), velocity-transmission ratio along a direction (eq. 5.60), condition number, smallest
// singular value, and the manipulability ellipsoid. All are computed from one SVD of J (m x n,
// m <= 6), so they agree with each other to rounding.
#include <Eigen/Core>
#include <vector>

#include "kinematics/kinematics.hpp"

namespace armstudy::metrics {

// Which rows of the geometric TCP Jacobian J_W_tcp = [J_T; J_R] a measure uses.
enum class MeasureSpace {
  Translational,  // J_T (3 x n): units m/rad or 1 (prismatic); ellipsoids live here
  Full,           // [J_T; J_R] (6 x n): mixes m and rad, so values depend on the length unit
};
const char* toString(MeasureSpace s);
bool parseMeasureSpace(const std::string& text, MeasureSpace& out);
inline int measureRows(MeasureSpace s) { return s == MeasureSpace::Translational ? 3 : 6; }

struct DexterityMeasures {
  double manipulability = 0;  // Yoshikawa sqrt(det(J J^T)) = product of singular values (eq. 5.59)
  double transmission =
      0;  // beta along u (eq. 5.60); 0 when no direction was given or J is singular along u
  double condition = 0;          // sigma_max / sigma_min (+inf when singular)
  double inverse_condition = 0;  // sigma_min / sigma_max in [0, 1], finite everywhere (for maps)
  double sigma_min = 0;          // smallest singular value
  double sigma_max = 0;
};

// Measures of J (m x n, m <= 6). `u` (size m, unit length) is optional: pass an empty vector to
// skip the transmission ratio. Singular values below `kSingularValueFloor * sigma_max` count as 0.
DexterityMeasures computeMeasures(const Eigen::Ref<const Eigen::MatrixXd>& J,
                                  const Eigen::Ref<const Eigen::VectorXd>& u);

// The same measures taken from the rows `space` of a workspace's TCP Jacobian; u_W is the
// translational direction (3-vector, padded with zero angular rows in the full space).
DexterityMeasures tcpMeasures(const KinematicsWorkspace& ws, MeasureSpace space,
                              const Eigen::Vector3d& u_W, bool with_direction);

// Manipulability ellipsoid of the translational Jacobian: {v = J_T qd : |qd| <= 1}. Principal axes
// are the left singular vectors (columns of axes_W, unit, right-handed), semi-axis lengths the
// singular values (descending). The ellipsoid tensor is axes diag(lengths^2) axes^T = J_T J_T^T.
struct Ellipsoid {
  Eigen::Matrix3d axes_W = Eigen::Matrix3d::Identity();
  Eigen::Vector3d lengths = Eigen::Vector3d::Zero();
};
Ellipsoid translationalEllipsoid(const KinematicsWorkspace& ws);

// Normalisation across a map as in thesis Fig. 3.6: every valid value divided by the largest valid
// value (so 1 is the best found). Invalid entries become `invalid_value`. Returns the maximum (0
// when there is no valid positive value; then valid entries become 0).
double normaliseToBest(std::vector<double>& values, const std::vector<unsigned char>& valid,
                       double invalid_value);

}  // namespace armstudy::metrics
