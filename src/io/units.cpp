#include "io/units.hpp"

#include <cctype>
#include <cmath>
#include <numbers>

#include "common/defaults.hpp"
#include "common/enum_names.hpp"
#include "common/format.hpp"

namespace armstudy {

constexpr const char* kDimensionNames[] = {"length", "angle", "linear velocity", "angular velocity",
                                           "dimensionless"};
const char* toString(Dimension d) { return enumName(d, kDimensionNames); }

constexpr const char* kDimensionUnits[] = {"m", "rad", "m/s", "rad/s", "1"};
const char* siUnit(Dimension d) { return enumName(d, kDimensionUnits); }

namespace {

struct Unit {
  const char* name;
  Dimension dim;
  double to_si;
};
const Unit kUnits[] = {
    {"m", Dimension::Length, 1.0},
    {"cm", Dimension::Length, 1e-2},
    {"mm", Dimension::Length, 1e-3},
    {"rad", Dimension::Angle, 1.0},
    {"deg", Dimension::Angle, std::numbers::pi / 180.0},
    {"m/s", Dimension::LinearVelocity, 1.0},
    {"mm/s", Dimension::LinearVelocity, 1e-3},
    {"rad/s", Dimension::AngularVelocity, 1.0},
    {"deg/s", Dimension::AngularVelocity, std::numbers::pi / 180.0},
    {"rpm", Dimension::AngularVelocity, 2.0 * std::numbers::pi / 60.0},
};

// Recursive-descent parser for: expr := term (('+'|'-') term)*; term := factor (('*'|'/') factor)*;
// factor := ('+'|'-') factor | number | 'pi' | '(' expr ')'.
class ExprParser {
 public:
  explicit ExprParser(const std::string& s) : s_(s) {}
  bool parse(double& v, std::string& error) {
    if (!expr(v)) {
      error = err_.empty() ? "malformed expression '" + s_ + "'" : err_;
      return false;
    }
    skipWs();
    if (pos_ != s_.size()) {
      error = "unexpected '" + s_.substr(pos_) + "' in '" + s_ + "'";
      return false;
    }
    return true;
  }

 private:
  void skipWs() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  // operand ((op1|op2) operand)*, left to right: apply(op, v, r) combines (false: an error).
  template <class Apply>
  bool chain(double& v, char op1, char op2, bool (ExprParser::*operand)(double&), Apply apply) {
    if (!(this->*operand)(v)) return false;
    for (;;) {
      skipWs();
      if (pos_ < s_.size() && (s_[pos_] == op1 || s_[pos_] == op2)) {
        const char op = s_[pos_++];
        double r;
        if (!(this->*operand)(r) || !apply(op, v, r)) return false;
      } else {
        return true;
      }
    }
  }
  bool expr(double& v) {
    return chain(v, '+', '-', &ExprParser::term, [](char op, double& l, double r) {
      l = op == '+' ? l + r : l - r;
      return true;
    });
  }
  bool term(double& v) {
    return chain(v, '*', '/', &ExprParser::factor, [this](char op, double& l, double r) {
      if (op == '/' && r == 0.0) {
        err_ = "division by zero in '" + s_ + "'";
        return false;
      }
      l = op == '*' ? l * r : l / r;
      return true;
    });
  }
  bool factor(double& v) {
    skipWs();
    if (pos_ >= s_.size()) return false;
    const char c = s_[pos_];
    if (c == '+' || c == '-') {
      ++pos_;
      if (!factor(v)) return false;
      if (c == '-') v = -v;
      return true;
    }
    if (c == '(') {
      ++pos_;
      if (!expr(v)) return false;
      skipWs();
      if (pos_ >= s_.size() || s_[pos_] != ')') {
        err_ = "missing ')' in '" + s_ + "'";
        return false;
      }
      ++pos_;
      return true;
    }
    if (s_.compare(pos_, 2, "pi") == 0) {
      pos_ += 2;
      v = std::numbers::pi;
      return true;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      std::size_t used = 0;
      try {
        v = std::stod(s_.substr(pos_), &used);
      } catch (...) {
        return false;
      }
      pos_ += used;
      return true;
    }
    return false;
  }
  const std::string& s_;
  std::size_t pos_ = 0;
  std::string err_;
};

}  // namespace

bool parseQuantity(const std::string& text, Dimension dim, double& value_si, std::string& error) {
  // Split off a trailing unit: the last whitespace-separated token if it starts with a letter
  // other than the constant "pi".
  std::string body = text, unit;
  const auto last = text.find_last_not_of(" \t");
  if (last == std::string::npos) {
    error = "empty value";
    return false;
  }
  auto start = text.find_last_of(" \t", last);
  start = start == std::string::npos ? 0 : start + 1;
  const std::string tail = text.substr(start, last - start + 1);
  if (!tail.empty() && std::isalpha(static_cast<unsigned char>(tail[0])) &&
      tail.rfind("pi", 0) != 0) {
    unit = tail;
    body = text.substr(0, start);
  }
  double v = 0;
  ExprParser p(body);
  if (!p.parse(v, error)) return false;
  double scale = 1.0;
  if (unit.empty() && (dim == Dimension::Length || dim == Dimension::LinearVelocity)) {
    error =
        std::string("a ") + toString(dim) + " written as a string needs its unit ('" + text +
        (dim == Dimension::Length ? " mm' or '" + text + " m'" : " mm/s' or '" + text + " m/s'") +
        "); a bare number is SI";
    return false;
  }
  if (!unit.empty()) {
    const Unit* u = nullptr;
    for (const auto& cand : kUnits)
      if (unit == cand.name) u = &cand;
    if (!u) {
      error = "unknown unit '" + unit + "' (a " + toString(dim) + " takes " +
              (dim == Dimension::Length            ? "m, cm or mm"
               : dim == Dimension::Angle           ? "rad or deg"
               : dim == Dimension::LinearVelocity  ? "m/s or mm/s"
               : dim == Dimension::AngularVelocity ? "rad/s, deg/s or rpm"
                                                   : "no unit") +
              ")";
      return false;
    }
    if (u->dim != dim) {
      error = std::string("unit '") + unit + "' is a " + toString(u->dim) +
              ", but this value is a " + toString(dim);
      return false;
    }
    scale = u->to_si;
  }
  value_si = v * scale;
  if (!std::isfinite(value_si)) {
    error = "value '" + text + "' is not finite";
    return false;
  }
  return true;
}

double plausibleMagnitude(Dimension dim) {
  switch (dim) {
    case Dimension::Length:
      return kMaxLength_m;
    case Dimension::Angle:
      return kMaxAngle_rad;
    case Dimension::LinearVelocity:
      return kMaxLinearVelocity_mps;
    case Dimension::AngularVelocity:
      return kMaxAngularVelocity_radps;
    case Dimension::Dimensionless:
      return kMaxDimensionless;
  }
  return kMaxPlainNumber;
}

std::string implausible(double value_si, const Dimension* dim) {
  if (!std::isfinite(value_si)) return "value is not finite (NaN or Inf)";
  const double limit = dim ? plausibleMagnitude(*dim) : kMaxPlainNumber;
  if (std::abs(value_si) <= limit) return {};
  return "value " + formatG(value_si, 6) + " is not plausible: |value| must be at most " +
         formatScientific(limit, 0) + (dim ? std::string(" (SI, ") + toString(*dim) + ")" : "");
}

std::string implausibleWeight(double w, bool zero_allowed) {
  if (!std::isfinite(w)) return "value is not finite (NaN or Inf)";
  if ((zero_allowed && w == 0) || (w >= defaults::kMinWeight && w <= defaults::kMaxWeight))
    return {};
  return formatG(w, 6) + " is not a plausible weight or gain: it lies in [" +
         formatG(defaults::kMinWeight, 6) + ", " + formatG(defaults::kMaxWeight, 6) + "]" +
         (zero_allowed ? " or is 0" : "");
}

}  // namespace armstudy
