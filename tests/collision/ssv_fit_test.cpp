// Mesh -> SSV fitting: containment of every vertex (and of sampled surface points) checked with
// CGAL's own point distances, STL/OFF readers, bad meshes, and the fit-ssv command end to end.
#include "collision/ssv_fit.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/squared_distance_3.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/units.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;
using Eigen::Vector3d;
namespace fs = std::filesystem;

namespace {

using InexactKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// A contained point may sit on the surface up to rounding.
constexpr double kInside_m = 1e-12;

struct TestMesh {
  std::vector<Vector3d> v;
  std::vector<std::array<int, 3>> f;
};

// Closed prism: a polygon (counter-clockwise in the y-z plane, triangulated as a fan from
// corner 0, so convex or star-shaped from corner 0) extruded along x from 0 to `length`.
TestMesh prism(const std::vector<Eigen::Vector2d>& poly, double length, const Vector3d& offset) {
  TestMesh m;
  const int n = static_cast<int>(poly.size());
  for (double x : {0.0, length})
    for (const auto& p : poly) m.v.push_back(offset + Vector3d(x, p.x(), p.y()));
  for (int i = 1; i + 1 < n; ++i) {
    m.f.push_back({0, i + 1, i});          // x = 0 cap, facing -x
    m.f.push_back({n, n + i, n + i + 1});  // x = length cap, facing +x
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.f.push_back({i, j, n + j});
    m.f.push_back({i, n + j, n + i});
  }
  return m;
}

TestMesh box(double lx, double ly, double lz) {
  return prism({{-ly / 2, -lz / 2}, {ly / 2, -lz / 2}, {ly / 2, lz / 2}, {-ly / 2, lz / 2}}, lx,
               Vector3d(-lx / 2, 0, 0));
}

TestMesh tube(double length, double radius, int sides) {
  std::vector<Eigen::Vector2d> poly;
  for (int i = 0; i < sides; ++i)
    poly.emplace_back(radius * std::cos(2 * M_PI * i / sides),
                      radius * std::sin(2 * M_PI * i / sides));
  return prism(poly, length, Vector3d(0, 0.02, -0.01));
}

// An L-shaped plate bracket (star-shaped from corner 0).
TestMesh bracket() {
  return prism({{0, 0}, {0.3, 0}, {0.3, 0.05}, {0.05, 0.05}, {0.05, 0.25}, {0, 0.25}}, 0.04,
               Vector3d::Zero());
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("armstudy_fit_test_" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

void writeOff(const std::string& path, const TestMesh& m, int drop_faces = 0) {
  std::ofstream os(path);
  os.precision(17);
  os << "OFF\n" << m.v.size() << " " << m.f.size() - drop_faces << " 0\n";
  for (const auto& p : m.v) os << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (std::size_t i = drop_faces; i < m.f.size(); ++i)
    os << "3 " << m.f[i][0] << " " << m.f[i][1] << " " << m.f[i][2] << "\n";
}

void writeAsciiStl(const std::string& path, const TestMesh& m, double scale) {
  std::ofstream os(path);
  os.precision(17);
  os << "solid t\n";
  for (const auto& f : m.f) {
    const Vector3d n = (m.v[f[1]] - m.v[f[0]]).cross(m.v[f[2]] - m.v[f[0]]).normalized();
    os << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vector3d p = m.v[f[k]] * scale;
      os << "vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
    os << "endloop\nendfacet\n";
  }
  os << "endsolid t\n";
}

// Distance of x from the nearest fitted volume's surface, with CGAL's point distances (an oracle
// independent of armstudy's distance code); <= 0 inside.
double cgalExcess(const std::vector<FittedSsv>& vols, const Vector3d& x) {
  const InexactKernel::Point_3 p(x.x(), x.y(), x.z());
  auto P = [](const Vector3d& v) { return InexactKernel::Point_3(v.x(), v.y(), v.z()); };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& v : vols) {
    double sq = 0;
    if (v.type == SsvType::Point) sq = CGAL::squared_distance(p, P(v.p[0]));
    if (v.type == SsvType::Line)
      sq = CGAL::squared_distance(p, InexactKernel::Segment_3(P(v.p[0]), P(v.p[1])));
    if (v.type == SsvType::Triangle)
      sq = CGAL::squared_distance(p, InexactKernel::Triangle_3(P(v.p[0]), P(v.p[1]), P(v.p[2])));
    best = std::min(best, std::sqrt(sq) - v.radius_m);
  }
  return best;
}

void checkContainment(const TestMesh& m, const SsvFitSummary& fit) {
  for (const auto& x : m.v) REQUIRE(cgalExcess(fit.volumes, x) <= kInside_m);
  // Stronger than the guarantee: random points on every face are inside too (the slab points
  // include the edge/plane crossings, so each slab's piece of the surface is enclosed).
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& f : m.f)
    for (int k = 0; k < 20; ++k) {
      double a = u(rng), b = u(rng);
      if (a + b > 1) {
        a = 1 - a;
        b = 1 - b;
      }
      const Vector3d x = m.v[f[0]] + a * (m.v[f[1]] - m.v[f[0]]) + b * (m.v[f[2]] - m.v[f[0]]);
      REQUIRE(cgalExcess(fit.volumes, x) <= kInside_m);
    }
  REQUIRE(fit.max_vertex_excess_m <= 0);
}

}  // namespace

TEST_CASE("fitted SSVs contain every vertex of the mesh they were fitted to") {
  TempDir dir;
  struct Case {
    const char* name;
    TestMesh mesh;
  };
  const Case cases[] = {{"box", box(0.2, 0.1, 0.05)},
                        {"long tube", tube(0.4, 0.04, 12)},
                        {"L bracket", bracket()},
                        {"cube", box(0.1, 0.1, 0.1)}};
  for (const auto& c : cases) {
    for (int max_volumes : {1, 2, 4}) {
      INFO(c.name << ", max " << max_volumes << " volumes");
      const std::string path = dir.file(std::string(c.name) + ".off");
      writeOff(path, c.mesh);
      SsvFitOptions o;
      o.max_volumes = max_volumes;
      const SsvFitSummary fit = fitSsvs(loadTriangleMesh(path, 1.0, kMaxLength_m), o);
      REQUIRE(!fit.volumes.empty());
      REQUIRE(static_cast<int>(fit.volumes.size()) <= max_volumes);
      REQUIRE(fit.mesh_vertices == static_cast<int>(c.mesh.v.size()));
      checkContainment(c.mesh, fit);
      CHECK(fit.swept_volume_m3 >= fit.mesh_volume_m3);
    }
  }
}

TEST_CASE("a long tube is fitted by a capsule close to its own size") {
  TempDir dir;
  const TestMesh m = tube(0.4, 0.04, 24);
  writeOff(dir.file("tube.off"), m);
  SsvFitOptions o;
  o.max_volumes = 1;
  const SsvFitSummary fit = fitSsvs(loadTriangleMesh(dir.file("tube.off"), 1.0, kMaxLength_m), o);
  REQUIRE(fit.volumes.size() == 1);
  CHECK(fit.volumes[0].type == SsvType::Line);
  // Circumradius of the 24-gon is the tube radius: the capsule radius is that (plus rounding).
  CHECK(fit.volumes[0].radius_m == Approx(0.04).margin(1e-6));
  // The cap rims lie at the full radius, so the core must span the whole length (0.4 m) and no
  // further: the tightest capsule of a flat-capped cylinder.
  CHECK((fit.volumes[0].p[1] - fit.volumes[0].p[0]).norm() == Approx(0.4).margin(1e-6));
  // A margin adds clearance to the radius.
  o.margin_m = 0.01;
  const SsvFitSummary wide = fitSsvs(loadTriangleMesh(dir.file("tube.off"), 1.0, kMaxLength_m), o);
  CHECK(wide.volumes[0].radius_m == Approx(0.05).margin(1e-6));
}

TEST_CASE("STL (ASCII, in millimetres) and OFF of the same solid give the same fit") {
  TempDir dir;
  const TestMesh m = bracket();
  writeOff(dir.file("b.off"), m);
  writeAsciiStl(dir.file("b.stl"), m, 1000.0);
  const TriangleMesh off = loadTriangleMesh(dir.file("b.off"), 1.0, kMaxLength_m);
  const TriangleMesh stl = loadTriangleMesh(dir.file("b.stl"), 0.001, kMaxLength_m);
  REQUIRE(stl.vertices.size() == m.v.size());  // STL corners are shared again
  SsvFitOptions o;
  const SsvFitSummary a = fitSsvs(off, o), b = fitSsvs(stl, o);
  REQUIRE(a.volumes.size() == b.volumes.size());
  CHECK(a.swept_volume_m3 == Approx(b.swept_volume_m3).epsilon(1e-9));
  checkContainment(m, b);
}

TEST_CASE("missing, empty, unsupported and non-closed meshes are InputErrors") {
  TempDir dir;
  auto expectError = [&](const std::string& path, const std::string& words) {
    try {
      loadTriangleMesh(path, 1.0, kMaxLength_m);
      FAIL("expected an InputError for " << path);
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == path);
      CHECK(e.key() == "mesh");
      CHECK(std::string(e.what()).find(words) != std::string::npos);
    }
  };
  expectError(dir.file("nothing.stl"), "cannot open");
  { std::ofstream(dir.file("empty.off")); }
  expectError(dir.file("empty.off"), "empty");
  {
    std::ofstream os(dir.file("nofaces.off"));
    os << "OFF\n0 0 0\n";
  }
  expectError(dir.file("nofaces.off"), "");
  writeOff(dir.file("open.off"), box(0.1, 0.1, 0.1), 2);  // one square face missing
  expectError(dir.file("open.off"), "not closed");
  writeOff(dir.file("box.obj"), box(0.1, 0.1, 0.1));
  expectError(dir.file("box.obj"), "unsupported");
}

TEST_CASE("fit-ssv writes the fitted volumes into a copy of the design, atomically and loadable") {
  TempDir dir;
  const std::string design = test::sourcePath("designs/final_prototype_7dof.toml");
  const TestMesh m = tube(0.35, 0.05, 16);
  writeOff(dir.file("upper_arm.off"), m);
  const std::string out = dir.file("fitted.toml");
  std::string log;
  const int rc = test::runCommand(test::binaryPath() + " fit-ssv " + design + " --link j3 --mesh " +
                                      dir.file("upper_arm.off") + " --max-volumes 2 --out " + out,
                                  log);
  INFO(log);
  REQUIRE(rc == 0);
  const Model before = loadDesign(design), after = loadDesign(out);
  std::vector<FittedSsv> j3;
  int others_before = 0, others_after = 0;
  for (const auto& v : before.collision.volumes) others_before += v.link != 2;
  for (const auto& v : after.collision.volumes) {
    if (v.link != 2) {
      ++others_after;
      continue;
    }
    FittedSsv f;
    f.type = v.type;
    f.p = v.p_L;
    f.radius_m = v.radius_m;
    j3.push_back(f);
  }
  CHECK(others_after == others_before);
  REQUIRE(!j3.empty());
  REQUIRE(j3.size() <= 2);
  for (const auto& x : m.v) CHECK(cgalExcess(j3, x) <= kInside_m);  // written and read back
  CHECK(after.joints.size() == before.joints.size());

  // Bad input: a missing mesh or an unknown link fails with exit 2 and writes nothing.
  const std::string out2 = dir.file("never.toml");
  CHECK(test::runCommand(test::binaryPath() + " fit-ssv " + design + " --link j3 --mesh " +
                             dir.file("missing.stl") + " --out " + out2,
                         log) == 2);
  CHECK(log.find("missing.stl") != std::string::npos);
  CHECK(test::runCommand(test::binaryPath() + " fit-ssv " + design + " --link j5 --mesh " +
                             dir.file("upper_arm.off") + " --out " + out2,
                         log) == 2);
  CHECK(log.find("no link named 'j5'") != std::string::npos);
  CHECK_FALSE(fs::exists(out2));

  // In place on a copy: the fitted tables replace the link's old ones; rerunning is idempotent.
  const std::string copy = dir.file("copy.toml");
  fs::copy_file(design, copy);
  REQUIRE(test::runCommand(test::binaryPath() + " fit-ssv " + copy + " --link j3 --mesh " +
                               dir.file("upper_arm.off") + " --in-place",
                           log) == 0);
  const std::string once = readFileOrThrow(copy);
  REQUIRE(test::runCommand(test::binaryPath() + " fit-ssv " + copy + " --link j3 --mesh " +
                               dir.file("upper_arm.off") + " --in-place",
                           log) == 0);
  CHECK(readFileOrThrow(copy) == once);
}
