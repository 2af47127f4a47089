#include "metrics/dexterity_measures.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "common/defaults.hpp"
#include "common/errors.hpp"

namespace armstudy::metrics {

const char* toString(MeasureSpace s) {
  return s == MeasureSpace::Translational ? "translational" : "full";
}

bool parseMeasureSpace(const std::string& text, MeasureSpace& out) {
  if (text == "translational") return out = MeasureSpace::Translational, true;
  if (text == "full") return out = MeasureSpace::Full, true;
  return false;
}

DexterityMeasures computeMeasures(const Eigen::Ref<const Eigen::MatrixXd>& J,
                                  const Eigen::Ref<const Eigen::VectorXd>& u) {
  using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxDof>;
  const int m = static_cast<int>(J.rows());
  ARMSTUDY_CHECK(m >= 1 && m <= 6, "computeMeasures: J must have 1 to 6 rows");
  ARMSTUDY_CHECK(u.size() == 0 || u.size() == m, "computeMeasures: u must be empty or of size m");
  // More rows than columns: J J^T is singular; zero columns give its m singular values.
  Mat Jm = J;
  if (m > J.cols()) Jm.conservativeResizeLike(Mat::Zero(m, m));
  // U only for the transmission ratio (eq. 5.60); the singular values do not depend on it.
  const bool transmission = u.size() == m;
  const Eigen::JacobiSVD<Mat> svd(Jm, transmission ? Eigen::ComputeFullU : 0);
  const auto& s = svd.singularValues();  // descending, size m
  DexterityMeasures d;
  d.sigma_max = s[0];
  d.sigma_min = s[m - 1];
  const double floor = defaults::kSingularValueFloor * std::max(d.sigma_max, 1e-300);
  double prod = 1;
  for (int k = 0; k < m; ++k) prod *= s[k];
  d.manipulability = d.sigma_min <= floor ? 0.0 : prod;  // eq. (5.59) without the minus sign
  d.inverse_condition = d.sigma_max > 0 ? d.sigma_min / d.sigma_max : 0.0;
  d.condition =
      d.sigma_min <= floor ? std::numeric_limits<double>::infinity() : d.sigma_max / d.sigma_min;
  if (transmission) {
    // Thesis eq. (5.60): beta = (u^T (J J^T)^-1 u)^(-1/2), with J J^T = U S^2 U^T.
    const Eigen::VectorXd c = svd.matrixU().transpose() * u;
    double q = 0;
    bool singular = false;
    for (int k = 0; k < m; ++k) {
      if (s[k] <= floor) {
        if (std::abs(c[k]) > defaults::kSingularValueFloor) singular = true;
        continue;
      }
      q += c[k] * c[k] / (s[k] * s[k]);
    }
    d.transmission = (singular || q <= 0) ? 0.0 : 1.0 / std::sqrt(q);
  }
  return d;
}

DexterityMeasures tcpMeasures(const KinematicsWorkspace& ws, MeasureSpace space,
                              const Eigen::Vector3d& u_W, bool with_direction) {
  const int m = measureRows(space);
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> u;
  if (with_direction) {
    u.setZero(m);
    u.head<3>() = u_W;
  }
  return computeMeasures(ws.J_W_tcp.topRows(m), u);
}

Ellipsoid translationalEllipsoid(const KinematicsWorkspace& ws) {
  const Jacobian3 J_T = ws.J_W_tcp.topRows<3>();
  const Eigen::JacobiSVD<Jacobian3> svd(J_T, Eigen::ComputeFullU);
  Ellipsoid e;
  e.axes_W = svd.matrixU();
  if (e.axes_W.determinant() < 0) e.axes_W.col(2) = -e.axes_W.col(2);
  e.lengths = svd.singularValues();
  return e;
}

double normaliseToBest(std::vector<double>& values, const std::vector<unsigned char>& valid,
                       double invalid_value) {
  ARMSTUDY_CHECK(values.size() == valid.size(), "normaliseToBest: size mismatch");
  double best = 0;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (valid[i] && values[i] > best) best = values[i];
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = !valid[i] ? invalid_value : (best > 0 ? values[i] / best : 0.0);
  return best;
}

}  // namespace armstudy::metrics
