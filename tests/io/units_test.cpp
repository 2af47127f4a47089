#include "io/units.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace armstudy;

TEST_CASE("quantities parse as written in the thesis, converted to SI", "[io][units]") {
  double v = 0;
  std::string err;
  REQUIRE(parseQuantity("pi/2", Dimension::Angle, v, err));
  CHECK(v == Approx(M_PI / 2).epsilon(1e-15));
  REQUIRE(parseQuantity("-pi/2", Dimension::Angle, v, err));
  CHECK(v == Approx(-M_PI / 2).epsilon(1e-15));
  REQUIRE(parseQuantity("90 deg", Dimension::Angle, v, err));
  CHECK(v == Approx(M_PI / 2).epsilon(1e-15));
  REQUIRE(parseQuantity("(1+1)*pi / 4 rad", Dimension::Angle, v, err));
  CHECK(v == Approx(M_PI / 2).epsilon(1e-15));
  REQUIRE(parseQuantity("230 mm", Dimension::Length, v, err));
  CHECK(v == Approx(0.23).epsilon(1e-15));
  REQUIRE(parseQuantity("0.75 + 0.1 m", Dimension::Length, v, err));
  CHECK(v == Approx(0.85).epsilon(1e-15));
  REQUIRE(parseQuantity("60 rpm", Dimension::AngularVelocity, v, err));
  CHECK(v == Approx(2 * M_PI).epsilon(1e-15));
  REQUIRE(parseQuantity("1e-3 m", Dimension::Length, v, err));
  CHECK(v == Approx(1e-3).epsilon(1e-15));
}

TEST_CASE("quantities with the wrong unit, unknown units or bad syntax are rejected",
          "[io][units][bad-input]") {
  double v = 0;
  std::string err;
  CHECK_FALSE(parseQuantity("90 deg", Dimension::Length, v, err));
  CHECK(err.find("angle") != std::string::npos);
  CHECK_FALSE(parseQuantity("0.3 mm", Dimension::Angle, v, err));
  CHECK_FALSE(parseQuantity("3 furlong", Dimension::Length, v, err));
  CHECK(err.find("furlong") != std::string::npos);
  // A length string without a unit: refused with the way out, not read as metres.
  CHECK_FALSE(parseQuantity("924.5", Dimension::Length, v, err));
  CHECK(err.find("'924.5 mm'") != std::string::npos);
  CHECK_FALSE(parseQuantity("0.2", Dimension::LinearVelocity, v, err));
  CHECK(err.find("m/s") != std::string::npos);
  CHECK_FALSE(parseQuantity("pi/", Dimension::Angle, v, err));
  CHECK_FALSE(parseQuantity("(pi", Dimension::Angle, v, err));
  CHECK_FALSE(parseQuantity("1/0", Dimension::Angle, v, err));
  CHECK_FALSE(parseQuantity("", Dimension::Angle, v, err));
  CHECK_FALSE(parseQuantity("nan", Dimension::Angle, v, err));
}
