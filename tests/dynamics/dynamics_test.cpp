// Rigid-body dynamics against independent oracles: orocos-kdl's ChainIdSolver_RNE and
// ChainDynParam, a second algorithm for M (composite bodies vs. Newton-Euler with unit
// accelerations), a closed-form pendulum, finite differences of the potential energy, the kinetic
// energy from link velocities, and energy conservation of a simulated frictionless swing.
#include "dynamics/dynamics.hpp"

#include <Eigen/Eigenvalues>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <new>

#include "alloc_counter.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "kdl_support.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

using armstudy::test::g_allocations;  // tests/alloc_counter.hpp replaces the allocation functions

namespace {

constexpr double kKdlRelTolerance = 1e-9;       // relative agreement with orocos-kdl
constexpr double kAlgebraTolerance = 1e-10;     // two exact algorithms on the same data (relative)
constexpr double kRoundTripTolerance = 1e-8;    // inverse then forward dynamics (relative)
constexpr double kEnergyDriftTolerance = 1e-6;  // relative drift of RK4 over the swing
constexpr double kFdGravityTolerance = 1e-6;    // dV/dq by central differences [N m] (relative)
constexpr double kClosedFormTolerance = 1e-12;  // closed-form pendulum [N m]
constexpr double kFdLagrangeTolerance = 1e-7;   // Lagrange's equations by differences (relative)
constexpr double kFdTimeStep = 1e-4;            // d/dt along a path by central differences [s]
constexpr double kFdVelocityStep = 1e-3;        // dT/dqd by central differences [rad/s or m/s]

Eigen::VectorXd randomVector(int n, double scale, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

double relErr(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// The joint torques of Lagrange's equations, tau_i = d/dt dT/dqd_i - dT/dq_i + dV/dq_i, from
// central differences of the energies alone (mechanicalEnergy: the kinetic energy from the links'
// velocities, the potential from their centres of mass), with d/dt taken along the path
// q(t) = q + qd t + qdd t^2 / 2. An oracle for inverse dynamics that shares no force recursion with
// Newton-Euler. T is quadratic in qd, so its qd-difference is exact up to rounding.
Eigen::VectorXd lagrangeTorques(const RigidBodyModel& rbm, DynamicsWorkspace& ws,
                                const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                const Eigen::VectorXd& qdd) {
  const int n = static_cast<int>(q.size());
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const auto kinetic = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
    return mechanicalEnergy(rbm, ws, qq, vv).kinetic_J;
  };
  // dT/dqd_i at time t on the path.
  const auto momentum = [&](int i, double t) {
    const Eigen::VectorXd qq = q + t * qd + 0.5 * t * t * qdd, vv = qd + t * qdd;
    Eigen::VectorXd vp = vv, vm = vv;
    vp[i] += kFdVelocityStep;
    vm[i] -= kFdVelocityStep;
    return (kinetic(qq, vp) - kinetic(qq, vm)) / (2 * kFdVelocityStep);
  };
  Eigen::VectorXd tau(n);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += kFdStep;
    qm[i] -= kFdStep;
    const double dp_dt = (momentum(i, kFdTimeStep) - momentum(i, -kFdTimeStep)) / (2 * kFdTimeStep);
    const double dT_dq = (kinetic(qp, qd) - kinetic(qm, qd)) / (2 * kFdStep);
    const double dV_dq = (mechanicalEnergy(rbm, ws, qp, zero).potential_J -
                          mechanicalEnergy(rbm, ws, qm, zero).potential_J) /
                         (2 * kFdStep);
    tau[i] = dp_dt - dT_dq + dV_dq;
  }
  return tau;
}

// Every shipped design with rotor inertias attached (the drive issue ships the real [[drive]]
// data; here plausible values so the armature path is exercised against KDL's joint inertia).
Model withTestDrives(Model m) {
  m.drives.clear();
  for (int i = 0; i < m.dof(); ++i) {
    Drive d;
    d.joint = m.joints[i].name;
    d.gear_ratio = m.joints[i].type == JointType::Revolute ? 100.0 : 2 * 3.14159265358979 / 0.01;
    d.torque_constant_NmpA = 0.1;
    d.rotor_inertia_kgm2 = 1e-5 * (1 + i);
    m.drives.push_back(d);
  }
  return m;
}

std::string designText(const std::string& inertia, const std::string& extra = "") {
  return R"(
[design]
name = "pendulum"
[[joint]]
name = "j1"
type = "revolute"
x = 0
y = 0
z = 0
alpha = "pi/2"
beta = 0
gamma = 0
min = "-180 deg"
max = "180 deg"
[tcp]
x = 0.5
)" + inertia +
         extra;
}

}  // namespace

TEST_CASE("Newton-Euler agrees with orocos-kdl ChainIdSolver_RNE on random states",
          "[dynamics][oracle]") {
  std::mt19937_64 rng(2024);
  for (const auto& rel : shippedDesigns()) {
    Model m = withTestDrives(loadDesign(sourcePath(rel)));
    m.base = PoseXYZABG{0.2, -0.1, 0.3, 0.15, -0.1, 0.4};  // a tilted platform
    m.finalize();
    for (int variant = 0; variant < 4; ++variant) {
      DynamicsOptions opt;
      opt.include_payload = variant % 2 == 0;
      opt.include_rotor_inertia = variant >= 2;
      opt.g_W = variant == 3 ? Eigen::Vector3d(1.2, -0.7, -9.7) : Eigen::Vector3d(0, 0, -9.81);
      const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
      DynamicsWorkspace ws(rbm);
      const KDL::Chain chain = toKdlDynamicChain(m, opt.include_payload, opt.include_rotor_inertia);
      KDL::ChainIdSolver_RNE kdl(chain, KDL::Vector(opt.g_W.x(), opt.g_W.y(), opt.g_W.z()));
      const int n = m.dof();
      KDL::JntArray qk(n), qdk(n), qddk(n), tk(n);
      KDL::Wrenches fext(chain.getNrOfSegments(), KDL::Wrench::Zero());
      Eigen::VectorXd tau(n), tau_k(n);
      for (int trial = 0; trial < 100; ++trial) {
        const Eigen::VectorXd q = randomConfiguration(m, rng);
        const Eigen::VectorXd qd = randomVector(n, 2.0, rng);
        const Eigen::VectorXd qdd = randomVector(n, 5.0, rng);
        for (int i = 0; i < n; ++i) qk(i) = q[i], qdk(i) = qd[i], qddk(i) = qdd[i];
        REQUIRE(kdl.CartToJnt(qk, qdk, qddk, fext, tk) >= 0);
        for (int i = 0; i < n; ++i) tau_k[i] = tk(i);
        inverseDynamics(rbm, ws, q, qd, qdd, tau);
        INFO(rel << " variant " << variant << " trial " << trial);
        REQUIRE(relErr(tau, tau_k) < kKdlRelTolerance);
      }
    }
  }
}

TEST_CASE("mass matrix agrees with orocos-kdl ChainDynParam and is symmetric positive definite",
          "[dynamics][oracle]") {
  std::mt19937_64 rng(99);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    const RigidBodyModel rbm = makeRigidBodyModel(m);
    DynamicsWorkspace ws(rbm);
    const KDL::Chain chain = toKdlDynamicChain(m, true, false);
    KDL::ChainDynParam kdl(chain, KDL::Vector(0, 0, -9.81));
    const int n = m.dof();
    KDL::JntArray qk(n);
    KDL::JntSpaceInertiaMatrix Mk(n);
    for (int trial = 0; trial < 100; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      for (int i = 0; i < n; ++i) qk(i) = q[i];
      REQUIRE(kdl.JntToMass(qk, Mk) >= 0);
      massMatrix(rbm, ws, q);
      const Eigen::MatrixXd M = ws.M;
      const double scale = std::max(1.0, Mk.data.cwiseAbs().maxCoeff());
      CHECK((M - Mk.data).cwiseAbs().maxCoeff() / scale < kKdlRelTolerance);
      CHECK((M - M.transpose()).cwiseAbs().maxCoeff() == 0.0);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
      CHECK(es.eigenvalues().minCoeff() > 0.0);
    }
  }
}

TEST_CASE("M qdd + h equals Newton-Euler, M equals RNEA with unit accelerations",
          "[dynamics][consistency]") {
  std::mt19937_64 rng(5);
  for (const auto& rel : shippedDesigns()) {
    const Model m = withTestDrives(loadDesign(sourcePath(rel)));
    DynamicsOptions opt;
    opt.include_rotor_inertia = true;
    const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
    DynamicsWorkspace ws(rbm);
    const int n = m.dof();
    Eigen::VectorXd h(n), tau(n), g(n), col(n);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      const Eigen::VectorXd qd = randomVector(n, 2.0, rng);
      const Eigen::VectorXd qdd = randomVector(n, 5.0, rng);
      massMatrix(rbm, ws, q);
      const Eigen::MatrixXd M = ws.M;
      biasForces(rbm, ws, q, qd, h);
      inverseDynamics(rbm, ws, q, qd, qdd, tau);
      CHECK(relErr(M * qdd + h, tau) < kAlgebraTolerance);
      gravityForces(rbm, ws, q, g);
      inverseDynamics(rbm, ws, q, zero, zero, tau);
      CHECK(relErr(g, tau) < kAlgebraTolerance);
      for (int k = 0; k < n; ++k) {
        // Column k of M = RNEA(q, 0, e_k) - g(q).
        inverseDynamics(rbm, ws, q, zero, Eigen::VectorXd::Unit(n, k), col);
        CHECK(relErr(M.col(k), col - g) < kAlgebraTolerance);
      }
    }
  }
}

TEST_CASE("inverse then forward dynamics returns the accelerations", "[dynamics][consistency]") {
  std::mt19937_64 rng(17);
  for (const auto& rel : shippedDesigns()) {
    const Model m = loadDesign(sourcePath(rel));
    const RigidBodyModel rbm = makeRigidBodyModel(m);
    DynamicsWorkspace ws(rbm);
    const int n = m.dof();
    Eigen::VectorXd tau(n), qdd2(n);
    for (int trial = 0; trial < 100; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      const Eigen::VectorXd qd = randomVector(n, 2.0, rng);
      const Eigen::VectorXd qdd = randomVector(n, 5.0, rng);
      inverseDynamics(rbm, ws, q, qd, qdd, tau);
      REQUIRE(forwardDynamics(rbm, ws, q, qd, tau, qdd2) == ForwardDynamicsStatus::Ok);
      CHECK(relErr(qdd2, qdd) < kRoundTripTolerance);
    }
  }
}

TEST_CASE("kinetic energy from link velocities equals qd^T M qd / 2, gravity is dV/dq",
          "[dynamics][consistency][fd]") {
  std::mt19937_64 rng(23);
  for (const auto& rel : shippedDesigns()) {
    Model m = withTestDrives(loadDesign(sourcePath(rel)));
    m.base = PoseXYZABG{0.1, 0.2, -0.3, 0.2, 0.1, -0.5};
    m.finalize();
    DynamicsOptions opt;
    opt.include_rotor_inertia = true;
    opt.g_W = Eigen::Vector3d(0.5, 0.3, -9.8);
    const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
    DynamicsWorkspace ws(rbm);
    const int n = m.dof();
    Eigen::VectorXd g(n);
    for (int trial = 0; trial < 30; ++trial) {
      const Eigen::VectorXd q = randomConfiguration(m, rng);
      const Eigen::VectorXd qd = randomVector(n, 2.0, rng);
      massMatrix(rbm, ws, q);
      const double T_M = 0.5 * qd.dot(ws.M * qd);
      const MechanicalEnergy e = mechanicalEnergy(rbm, ws, q, qd);
      CHECK(std::abs(e.kinetic_J - T_M) < kAlgebraTolerance * std::max(1.0, T_M));
      gravityForces(rbm, ws, q, g);
      for (int i = 0; i < n; ++i) {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += kFdStep;
        qm[i] -= kFdStep;
        const double dV = (mechanicalEnergy(rbm, ws, qp, qd).potential_J -
                           mechanicalEnergy(rbm, ws, qm, qd).potential_J) /
                          (2 * kFdStep);
        CHECK(std::abs(dV - g[i]) < kFdGravityTolerance * std::max(1.0, std::abs(g[i])));
      }
    }
  }
}

TEST_CASE("energy is conserved in a frictionless simulated swing (RK4)", "[dynamics][simulation]") {
  for (const auto& rel : shippedDesigns()) {
    const Model m = withTestDrives(loadDesign(sourcePath(rel)));
    DynamicsOptions opt;
    opt.include_rotor_inertia = true;
    const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
    DynamicsWorkspace ws(rbm);
    const int n = m.dof();
    // Start away from rest, no joint torques: the arm swings under gravity.
    Eigen::VectorXd q(n), qd(n);
    for (int i = 0; i < n; ++i) {
      q[i] =
          0.3 * (m.joints[i].limits.q_min + m.joints[i].limits.q_max) / 2 + 0.2 * std::sin(1.0 + i);
      qd[i] = 0.5 * std::cos(2.0 + i);
    }
    const Eigen::VectorXd Q = Eigen::VectorXd::Zero(n);
    const double dt = 1e-3, t_end = 1.0;
    auto deriv = [&](const Eigen::VectorXd& x, Eigen::VectorXd& dx) {
      Eigen::VectorXd acc(n);
      REQUIRE(forwardDynamics(rbm, ws, x.head(n), x.tail(n), Q, acc) == ForwardDynamicsStatus::Ok);
      dx.resize(2 * n);
      dx << x.tail(n), acc;
    };
    Eigen::VectorXd x(2 * n), k1, k2, k3, k4;
    x << q, qd;
    const double E0 = mechanicalEnergy(rbm, ws, q, qd).total();
    double max_speed = 0;
    for (double t = 0; t < t_end - 0.5 * dt; t += dt) {
      deriv(x, k1);
      deriv(x + 0.5 * dt * k1, k2);
      deriv(x + 0.5 * dt * k2, k3);
      deriv(x + dt * k3, k4);
      x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      max_speed = std::max(max_speed, x.tail(n).cwiseAbs().maxCoeff());
    }
    const MechanicalEnergy e1 = mechanicalEnergy(rbm, ws, x.head(n), x.tail(n));
    INFO(rel << ": E0 = " << E0 << " E1 = " << e1.total() << " kinetic " << e1.kinetic_J);
    CHECK(max_speed > 1.0);  // it really swung
    CHECK(std::abs(e1.total() - E0) / std::max(1.0, e1.kinetic_J) < kEnergyDriftTolerance);
  }
}

TEST_CASE("closed-form pendulum: tau = (I_zz + m l^2) qdd + m g l cos(q)",
          "[dynamics][closed-form]") {
  // Joint axis horizontal (alpha = pi/2: z1 along -y of W), link along x1 with a point-like mass.
  const double m = 2.0, l = 0.4, Izz = 0.01;
  const Model model =
      parseDesign(designText("[[inertia]]\nlink = \"j1\"\nmass = 2.0\ncom = [0.4, 0, 0]\n"
                             "inertia = [0.005, 0.005, 0.01, 0, 0, 0]\n"),
                  "pendulum.toml");
  const RigidBodyModel rbm = makeRigidBodyModel(model);
  DynamicsWorkspace ws(rbm);
  Eigen::VectorXd q(1), qd(1), qdd(1), tau(1);
  for (double angle : {-2.0, -0.5, 0.0, 0.7, 1.9}) {
    q[0] = angle;
    qd[0] = 1.3;  // no velocity-dependent torque on a single joint
    qdd[0] = -0.8;
    inverseDynamics(rbm, ws, q, qd, qdd, tau);
    // x1 = (cos q, 0, sin q) in W; gravity torque about z1 = -y: -m g l cos(q) * (-1).
    const double expected = (Izz + m * l * l) * qdd[0] + m * 9.81 * l * std::cos(angle);
    CHECK(std::abs(tau[0] - expected) < kClosedFormTolerance);
  }
}

TEST_CASE("bad inertial and drive data are input errors naming file, line and key",
          "[dynamics][input]") {
  auto expectError = [](const std::string& text, const std::string& key) {
    try {
      (void)parseDesign(text, "bad.toml");
      FAIL("no InputError for key " << key);
    } catch (const InputError& e) {
      CHECK(e.file() == "bad.toml");
      CHECK(e.line() > 0);
      CHECK(e.key().find(key) != std::string::npos);
    }
  };
  const std::string com = "com = [0.4, 0, 0]\n";
  expectError(designText("[[inertia]]\nlink = \"j1\"\nmass = -1.0\n" + com +
                         "inertia = [0.005, 0.005, 0.01, 0, 0, 0]\n"),
              "mass");
  // Indefinite (a negative principal moment). A zero moment (a thin rod, a point mass) is a body.
  CHECK(parseDesign(designText("[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com +
                               "inertia = [0.005, 0.005, 0.0, 0, 0, 0]\n"),
                    "rod.toml")
            .inertias[0]
            .given);
  CHECK(parseDesign(designText("[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com +
                               "inertia = [0, 0, 0, 0, 0, 0]\n"),
                    "point.toml")
            .inertias[0]
            .given);
  expectError(designText("[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com +
                         "inertia = [0.01, 0.01, 0.01, 0.02, 0, 0]\n"),
              "inertia");
  // Positive definite but Izz > Ixx + Iyy: no physical body has it.
  expectError(designText("[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com +
                         "inertia = [0.001, 0.002, 0.01, 0, 0, 0]\n"),
              "inertia");
  expectError(
      designText("[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com + "inertia = [0.01, 0.01]\n"),
      "inertia");
  expectError(designText("", "[payload]\nmass = -0.5\n"), "mass");
  const std::string inertia = "[[inertia]]\nlink = \"j1\"\nmass = 1.0\n" + com +
                              "inertia = [0.005, 0.005, 0.01, 0, 0, 0]\n";
  expectError(
      designText(inertia, "[[drive]]\njoint = \"j1\"\ngear_ratio = 0\ntorque_constant = 0.1\n"),
      "gear_ratio");
  expectError(
      designText(inertia, "[[drive]]\njoint = \"j1\"\ngear_ratio = 100\ntorque_constant = 0\n"),
      "torque_constant");
  expectError(designText(inertia,
                         "[[drive]]\njoint = \"j1\"\ngear_ratio = 100\ntorque_constant = 0.1\n"
                         "rotor_inertia = -1e-5\n"),
              "rotor_inertia");
  // The same body without the triangle violation is accepted.
  CHECK_NOTHROW(parseDesign(designText(inertia), "good.toml"));
}

TEST_CASE("dynamics of a design without inertial data is an input error", "[dynamics][input]") {
  const Model m = parseDesign(designText(""), "no_inertia.toml");
  try {
    (void)makeRigidBodyModel(m);
    FAIL("expected InputError");
  } catch (const InputError& e) {
    CHECK(e.file() == "no_inertia.toml");
    CHECK(e.key() == "inertia");
  }
}

TEST_CASE("inverse dynamics on 2 threads satisfies Lagrange's equations and equals 1 thread's",
          "[dynamics][determinism][fd]") {
  Model m = withTestDrives(loadDesign(sourcePath("designs/final_prototype_9dof.toml")));
  m.base = PoseXYZABG{0.1, -0.2, 0.3, -0.2, 0.15, 0.4};
  m.finalize();
  DynamicsOptions opt;
  opt.include_rotor_inertia = true;
  const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
  std::mt19937_64 rng(3);
  const int n = m.dof(), N = 200;
  std::vector<Eigen::VectorXd> qs, qds, qdds;
  for (int k = 0; k < N; ++k) {
    qs.push_back(randomConfiguration(m, rng));
    qds.push_back(randomVector(n, 1.0, rng));
    qdds.push_back(randomVector(n, 1.0, rng));
  }
  Eigen::MatrixXd serial(n, N), parallel(n, N), lagrange(n, N);
  {
    DynamicsWorkspace ws(rbm);
    for (int k = 0; k < N; ++k) {
      Eigen::VectorXd t(n);
      inverseDynamics(rbm, ws, qs[k], qds[k], qdds[k], t);
      serial.col(k) = t;
    }
  }
#pragma omp parallel num_threads(2)
  {
    DynamicsWorkspace ws(rbm);
#pragma omp for schedule(dynamic, 7)
    for (int k = 0; k < N; ++k) {
      Eigen::VectorXd t(n);
      inverseDynamics(rbm, ws, qs[k], qds[k], qdds[k], t);
      parallel.col(k) = t;
      lagrange.col(k) = lagrangeTorques(rbm, ws, qs[k], qds[k], qdds[k]);
    }
  }
  for (int k = 0; k < N; ++k) {
    INFO("sample " << k << ": Newton-Euler " << parallel.col(k).transpose() << ", Lagrange "
                   << lagrange.col(k).transpose());
    CHECK(relErr(parallel.col(k), lagrange.col(k)) < kFdLagrangeTolerance);
  }
  CHECK((serial - parallel).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("inverse dynamics, mass matrix and forward dynamics do not allocate",
          "[dynamics][memory]") {
  const Model m = loadDesign(sourcePath("designs/final_prototype_9dof.toml"));
  const RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  std::mt19937_64 rng(8);
  const int n = m.dof();
  const Eigen::VectorXd q = randomConfiguration(m, rng), qd = randomVector(n, 1.0, rng),
                        qdd = randomVector(n, 1.0, rng);
  Eigen::VectorXd tau(n), out(n);
  const long before = g_allocations.load();
  inverseDynamics(rbm, ws, q, qd, qdd, tau);
  biasForces(rbm, ws, q, qd, out);
  gravityForces(rbm, ws, q, out);
  massMatrix(rbm, ws, q);
  const ForwardDynamicsStatus status = forwardDynamics(rbm, ws, q, qd, tau, out);
  (void)mechanicalEnergy(rbm, ws, q, qd);
  const long after = g_allocations.load();
  CHECK(status == ForwardDynamicsStatus::Ok);
  CHECK(after - before == 0);
}

TEST_CASE("forward dynamics reports a singular mass matrix as a status", "[dynamics][status]") {
  // A massless pendulum without payload: M(q) = 0.
  const Model m = parseDesign(
      designText("[[inertia]]\nlink = \"j1\"\nmass = 0.0\ninertia = [0, 0, 0, 0, 0, 0]\n"),
      "massless.toml");
  const RigidBodyModel rbm = makeRigidBodyModel(m);
  DynamicsWorkspace ws(rbm);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1), qdd(1);
  CHECK(forwardDynamics(rbm, ws, q, q, q, qdd) == ForwardDynamicsStatus::SingularMassMatrix);
  CHECK(std::string(toString(ForwardDynamicsStatus::SingularMassMatrix)) == "singular_mass_matrix");
}
