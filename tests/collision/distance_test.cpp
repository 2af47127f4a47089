// Primitive distances against CGAL's exact squared distances (Epeck: exact rational arithmetic),
// symmetry, and named degenerate cases with closed-form answers.
#include "collision/distance.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::collision;
using Eigen::Vector3d;

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using P3 = K::Point_3;
using S3 = K::Segment_3;
using T3 = K::Triangle_3;

// The acceptance bound: agreement with the exact distance to 1e-9 m.
constexpr double kExactAgreement_m = 1e-9;
// A witness point lies on its core up to rounding of unit-scale coordinates.
constexpr double kWitnessOnCore_m = 1e-9;
// Same pair in swapped order: identical up to rounding.
constexpr double kSymmetry_m = 1e-12;
constexpr int kRandomPairsPerCase = 2500;

P3 cg(const Vector3d& v) { return P3(v.x(), v.y(), v.z()); }

double exactDistance(const K::FT& sq) { return std::sqrt(CGAL::to_double(CGAL::exact(sq))); }

// The oracle's view of a core: CGAL primitives, with degenerate shapes replaced by what they
// are (a zero-length segment by its point, a collinear triangle by its edges), since CGAL's
// triangle routines require non-degenerate input.
struct Exact {
  std::vector<P3> points;
  std::vector<S3> segments;
  std::vector<T3> triangles;
};
Exact exactCore(const Core& c) {
  Exact e;
  auto addSegment = [&](const Vector3d& a, const Vector3d& b) {
    const S3 s(cg(a), cg(b));
    if (s.is_degenerate())
      e.points.push_back(s.source());
    else
      e.segments.push_back(s);
  };
  if (c.n == 1) e.points.push_back(cg(c.p[0]));
  if (c.n == 2) addSegment(c.p[0], c.p[1]);
  if (c.n == 3) {
    const T3 t(cg(c.p[0]), cg(c.p[1]), cg(c.p[2]));
    if (!t.is_degenerate())
      e.triangles.push_back(t);
    else
      for (int i = 0; i < 3; ++i) addSegment(c.p[i], c.p[(i + 1) % 3]);
  }
  return e;
}

// CGAL 5.5 has no Segment_3-Triangle_3 distance: exact from the components (0 when CGAL's exact
// predicate says they intersect, else the minimum of endpoint-triangle and segment-edge distances).
K::FT exactSegmentTriangleSq(const S3& s, const T3& t) {
  if (CGAL::do_intersect(s, t)) return K::FT(0);
  K::FT m = CGAL::squared_distance(s.source(), t);
  m = CGAL::min(m, CGAL::squared_distance(s.target(), t));
  for (int i = 0; i < 3; ++i)
    m = CGAL::min(m, CGAL::squared_distance(s, S3(t.vertex(i), t.vertex((i + 1) % 3))));
  return m;
}

double exactCoreCore(const Core& a, const Core& b) {
  const Exact x = exactCore(a), y = exactCore(b);
  bool first = true;
  K::FT m(0);
  auto take = [&](const K::FT& v) {
    if (first || v < m) m = v;
    first = false;
  };
  for (const auto& p : x.points) {
    for (const auto& q : y.points) take(CGAL::squared_distance(p, q));
    for (const auto& s : y.segments) take(CGAL::squared_distance(p, s));
    for (const auto& t : y.triangles) take(CGAL::squared_distance(p, t));
  }
  for (const auto& s : x.segments) {
    for (const auto& q : y.points) take(CGAL::squared_distance(q, s));
    for (const auto& s2 : y.segments) take(CGAL::squared_distance(s, s2));
    for (const auto& t : y.triangles) take(exactSegmentTriangleSq(s, t));
  }
  for (const auto& t : x.triangles) {
    for (const auto& q : y.points) take(CGAL::squared_distance(q, t));
    for (const auto& s : y.segments) take(exactSegmentTriangleSq(s, t));
    for (const auto& t2 : y.triangles) take(CGAL::squared_distance(t, t2));
  }
  return exactDistance(m);
}

double exactPointCore(const Vector3d& x, const Core& c) {
  Core p;
  p.n = 1;
  p.p[0] = x;
  return exactCoreCore(p, c);
}

Core core(std::initializer_list<Vector3d> pts) {
  Core c;
  c.n = 0;
  for (const auto& p : pts) c.p[c.n++] = p;
  return c;
}

// Random cores mixing generic positions with the hard cases: near-parallel and parallel segments,
// coplanar and parallel triangles, touching and intersecting pairs, tiny and degenerate shapes.
struct Generator {
  std::mt19937_64 rng{20260611};
  std::uniform_real_distribution<double> u{-0.5, 0.5};
  Vector3d rnd() { return Vector3d(u(rng), u(rng), u(rng)); }
  int mode() { return std::uniform_int_distribution<int>(0, 6)(rng); }
  Core make(int n, const Core* relative_to, int m) {
    Core c;
    c.n = n;
    for (int i = 0; i < n; ++i) c.p[i] = rnd();
    if (!relative_to || relative_to->n < 2) return c;
    const Core& r = *relative_to;
    const Vector3d shift = rnd() * (m == 3 ? 1e-7 : 0.3);
    switch (m) {
      case 1:  // parallel / near-parallel copies, translated
        for (int i = 0; i < n; ++i)
          c.p[i] = r.p[i % r.n] + shift + (i >= r.n ? Vector3d(rnd() * 0.2) : Vector3d::Zero());
        if (n >= 2) c.p[1] = c.p[0] + (r.p[1] - r.p[0]) * (0.5 + u(rng)) + rnd() * 1e-9;
        break;
      case 2:  // coplanar with r (when r is a triangle) or collinear with r (segment)
        for (int i = 0; i < n; ++i) {
          const double s = 2 * u(rng), t = 2 * u(rng);
          c.p[i] = r.n == 3 ? Vector3d(r.p[0] + s * (r.p[1] - r.p[0]) + t * (r.p[2] - r.p[0]))
                            : Vector3d(r.p[0] + s * (r.p[1] - r.p[0]));
        }
        break;
      case 3:  // almost touching copies
        for (int i = 0; i < n; ++i) c.p[i] = r.p[i % r.n] + shift;
        break;
      case 5: {  // small angle (1e-5 .. 3e-2 rad) through the interior, crossing or just missing
        const Vector3d dir = r.p[1] - r.p[0];
        const Vector3d perp = dir.cross(rnd()).normalized();
        const double angle = std::pow(10.0, -5 + 3.5 * (u(rng) + 0.5));
        const Vector3d mid = r.p[0] + (0.5 + 0.8 * u(rng)) * dir + perp * (1e-3 * u(rng));
        const Vector3d d =
            (dir + angle * dir.norm() * perp.cross(dir).normalized()) * (0.5 + u(rng));
        c.p[0] = mid - 0.5 * d;
        if (n >= 2) c.p[1] = mid + 0.5 * d;
        if (n == 3) c.p[2] = mid + rnd() * 0.2;
        break;
      }
      case 4:  // degenerate: repeated points
        for (int i = 1; i < n; ++i) c.p[i] = c.p[0];
        break;
      default:
        break;
    }
    return c;
  }
};

void checkPair(const Core& a, const Core& b) {
  Vector3d ca, cb;
  const double sq = squaredDistanceCores(a, b, ca, cb);
  const double d = std::sqrt(sq);
  const double exact = exactCoreCore(a, b);
  INFO("types " << a.n << "-" << b.n << " d=" << d << " exact=" << exact);
  REQUIRE(std::abs(d - exact) <= kExactAgreement_m);
  REQUIRE(std::abs((ca - cb).norm() - d) <= kExactAgreement_m);
  REQUIRE(exactPointCore(ca, a) <= kWitnessOnCore_m);
  REQUIRE(exactPointCore(cb, b) <= kWitnessOnCore_m);
  Vector3d ca2, cb2;
  const double d2 = std::sqrt(squaredDistanceCores(b, a, cb2, ca2));
  REQUIRE(std::abs(d2 - d) <= kSymmetry_m);
}

void randomCase(int na, int nb) {
  Generator g;
  for (int k = 0; k < kRandomPairsPerCase; ++k) {
    const Core a = g.make(na, nullptr, 0);
    const Core b = g.make(nb, &a, g.mode());
    checkPair(a, b);
  }
}

}  // namespace

TEST_CASE("point-point distance matches CGAL exact on random pairs") { randomCase(1, 1); }
TEST_CASE("point-segment distance matches CGAL exact on random pairs") {
  randomCase(1, 2);
  randomCase(2, 1);
}
TEST_CASE("segment-segment distance matches CGAL exact on random pairs") { randomCase(2, 2); }
TEST_CASE("point-triangle distance matches CGAL exact on random pairs") {
  randomCase(1, 3);
  randomCase(3, 1);
}
TEST_CASE("segment-triangle distance matches CGAL exact on random pairs") {
  randomCase(2, 3);
  randomCase(3, 2);
}
TEST_CASE("triangle-triangle distance matches CGAL exact on random pairs") { randomCase(3, 3); }

TEST_CASE("named degenerate and parallel cases have their closed-form distances") {
  const Vector3d o(0, 0, 0), ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
  struct Case {
    const char* name;
    Core a, b;
    double expected;
  };
  const Case cases[] = {
      {"coincident points", core({ex}), core({ex}), 0.0},
      {"zero-length segment acts as a point", core({ey, ey}), core({o, ex}), 1.0},
      {"both segments zero-length", core({ey, ey}), core({ez, ez}), std::sqrt(2.0)},
      {"parallel overlapping segments", core({o, 2 * ex}), core({ex + 0.3 * ey, 3 * ex + 0.3 * ey}),
       0.3},
      {"parallel disjoint segments (end gap)", core({o, ex}),
       core({2 * ex + 0.4 * ey, 3 * ex + 0.4 * ey}), std::sqrt(1.0 + 0.16)},
      {"anti-parallel segments", core({o, 2 * ex}), core({3 * ex + 0.2 * ez, 1.5 * ex + 0.2 * ez}),
       0.2},
      {"collinear overlapping segments", core({o, 2 * ex}), core({ex, 3 * ex}), 0.0},
      {"collinear disjoint segments", core({o, ex}), core({1.5 * ex, 3 * ex}), 0.5},
      {"crossing segments", core({-ex, ex}), core({-ey, ey}), 0.0},
      {"skew segments", core({-ex, ex}), core({-ey + 0.7 * ez, ey + 0.7 * ez}), 0.7},
      {"point in triangle plane inside", core({0.2 * ex + 0.2 * ey}), core({o, ex, ey}), 0.0},
      {"point above triangle interior", core({0.2 * ex + 0.2 * ey + 0.3 * ez}), core({o, ex, ey}),
       0.3},
      {"point beyond a triangle corner", core({-ex - ey}), core({o, ex, ey}), std::sqrt(2.0)},
      {"collinear triangle acts as its hull segment", core({0.5 * ex + ey}), core({o, ex, 2 * ex}),
       1.0},
      {"triangle with coincident corners", core({0.5 * ex + ez}), core({o, o, ex}), 1.0},
      {"segment parallel above triangle",
       core({0.1 * ex + 0.1 * ey + 0.5 * ez, 0.3 * ex + 0.1 * ey + 0.5 * ez}), core({o, ex, ey}),
       0.5},
      {"segment piercing triangle", core({0.2 * ex + 0.2 * ey - ez, 0.2 * ex + 0.2 * ey + ez}),
       core({o, ex, ey}), 0.0},
      {"segment in triangle plane crossing an edge", core({-ex + 0.2 * ey, 0.5 * ex + 0.2 * ey}),
       core({o, ex, ey}), 0.0},
      {"segment in plane outside", core({-ex - ey, -ex + ey}), core({o, ex, ey}), 1.0},
      {"parallel stacked triangles", core({o, ex, ey}),
       core({0.25 * ez, ex + 0.25 * ez, ey + 0.25 * ez}), 0.25},
      {"coplanar overlapping triangles", core({o, ex, ey}),
       core({0.1 * ex + 0.1 * ey, 2 * ex, 2 * ey}), 0.0},
      {"coplanar disjoint triangles", core({o, ex, ey}), core({2 * ex, 3 * ex, 2 * ex + ey}), 1.0},
      {"triangles sharing an edge", core({o, ex, ey}), core({ex, ey, ez}), 0.0},
      {"crossed triangles", core({-ex, ex, ey}),
       core({0.2 * ey - ez, 0.2 * ey + ez, 0.2 * ey + ex}), 0.0},
      {"identical triangles", core({o, ex, ey}), core({o, ex, ey}), 0.0},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    Vector3d ca, cb;
    const double d = std::sqrt(squaredDistanceCores(c.a, c.b, ca, cb));
    CHECK(d == Approx(c.expected).margin(test::kHandCheckTolerance));
    CHECK(exactCoreCore(c.a, c.b) == Approx(c.expected).margin(test::kHandCheckTolerance));
    checkPair(c.a, c.b);
  }
}

TEST_CASE("overlapping swept-sphere volumes report the penetration as a negative distance") {
  // Two capsules on skew axes 0.1 m apart with radii 0.08 and 0.05: penetration 0.03 m.
  const Core a = core({Vector3d(-1, 0, 0), Vector3d(1, 0, 0)});
  const Core b = core({Vector3d(0, -1, 0.1), Vector3d(0, 1, 0.1)});
  SsvDistance w;
  ssvDistance(a, 0.08, b, 0.05, w);
  CHECK(w.distance_m == Approx(-0.03).margin(test::kHandCheckTolerance));
  CHECK((w.n - Vector3d::UnitZ()).norm() <= test::kHandCheckTolerance);
  // Surface witnesses: on each sphere-swept surface, at core witness +/- radius along n.
  CHECK((w.p_a - Vector3d(0, 0, 0.08)).norm() <= test::kHandCheckTolerance);
  CHECK((w.p_b - Vector3d(0, 0, 0.05)).norm() <= test::kHandCheckTolerance);
  // Separated: distance = gap between the surfaces, witnesses on the surfaces.
  ssvDistance(core({Vector3d(0, 0, 0)}), 0.1, core({Vector3d(1, 0, 0), Vector3d(1, 1, 0)}), 0.2, w);
  CHECK(w.distance_m == Approx(0.7).margin(test::kHandCheckTolerance));
  CHECK((w.p_b - w.p_a).norm() == Approx(0.7).margin(test::kHandCheckTolerance));
  // Touching cores (crossing segments): distance is minus the radii, direction undefined (zero).
  ssvDistance(core({-Vector3d::UnitX(), Vector3d::UnitX()}), 0.1,
              core({-Vector3d::UnitY(), Vector3d::UnitY()}), 0.1, w);
  CHECK(w.distance_m == Approx(-0.2).margin(test::kHandCheckTolerance));
  CHECK(w.n.isZero());
}
