#include "stages/explore/explore_plots.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "common/format.hpp"

namespace armstudy::explore {

namespace {

constexpr double kW = 640, kH = 420, kMargin = 60;

std::string f(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}
std::string label(double v) { return formatG(v, 4); }
std::string esc(const std::string& s) {
  std::string o;
  for (char ch : s)
    o += ch == '<' ? "&lt;" : ch == '>' ? "&gt;" : ch == '&' ? "&amp;" : std::string(1, ch);
  return o;
}
void range(const std::vector<double>& v, double& lo, double& hi) {
  lo = *std::min_element(v.begin(), v.end());
  hi = *std::max_element(v.begin(), v.end());
  if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
}
std::string header(const std::string& title) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + f(kW) + "\" height=\"" + f(kH) +
         "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" "
         "fill=\"white\"/>\n"
         "<text x=\"" +
         f(kW / 2) + "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">" + esc(title) +
         "</text>\n";
}

}  // namespace

std::string scatterSvg(const std::vector<Candidate>& c, const std::vector<std::size_t>& front,
                       std::size_t base, const ExploreOptions& o, std::size_t kx, std::size_t ky) {
  std::vector<double> xs, ys;
  for (const Candidate& k : c) xs.push_back(k.values[kx]), ys.push_back(k.values[ky]);
  double x0, x1, y0, y1;
  range(xs, x0, x1);
  range(ys, y0, y1);
  auto X = [&](double v) { return kMargin + (v - x0) / (x1 - x0) * (kW - 2 * kMargin); };
  auto Y = [&](double v) { return kH - kMargin - (v - y0) / (y1 - y0) * (kH - 2 * kMargin); };
  std::ostringstream s;
  s << header("Pareto front: " + o.objectives[ky].label + " vs " + o.objectives[kx].label);
  s << "<rect x=\"" << f(kMargin) << "\" y=\"" << f(kMargin) << "\" width=\"" << f(kW - 2 * kMargin)
    << "\" height=\"" << f(kH - 2 * kMargin) << "\" fill=\"none\" stroke=\"black\"/>\n";
  s << "<text x=\"" << f(kW / 2) << "\" y=\"" << f(kH - 15) << "\" text-anchor=\"middle\">"
    << esc(o.objectives[kx].label) << "</text>\n";
  s << "<text x=\"15\" y=\"" << f(kH / 2) << "\" text-anchor=\"middle\" transform=\"rotate(-90 15 "
    << f(kH / 2) << ")\">" << esc(o.objectives[ky].label) << "</text>\n";
  s << "<text x=\"" << f(kMargin) << "\" y=\"" << f(kH - kMargin + 14) << "\">" << label(x0)
    << "</text>\n";
  s << "<text x=\"" << f(kW - kMargin) << "\" y=\"" << f(kH - kMargin + 14)
    << "\" text-anchor=\"end\">" << label(x1) << "</text>\n";
  s << "<text x=\"" << f(kMargin - 4) << "\" y=\"" << f(kH - kMargin) << "\" text-anchor=\"end\">"
    << label(y0) << "</text>\n";
  s << "<text x=\"" << f(kMargin - 4) << "\" y=\"" << f(kMargin + 8) << "\" text-anchor=\"end\">"
    << label(y1) << "</text>\n";
  for (std::size_t i = 0; i < c.size(); ++i)
    s << "<circle cx=\"" << f(X(xs[i])) << "\" cy=\"" << f(Y(ys[i])) << "\" r=\"3\" "
      << (c[i].feasible ? "fill=\"#999\"" : "fill=\"none\" stroke=\"#999\"") << "/>\n";
  for (std::size_t i : front)
    s << "<circle cx=\"" << f(X(xs[i])) << "\" cy=\"" << f(Y(ys[i]))
      << "\" r=\"4\" fill=\"#d62728\"/>\n";
  s << "<rect x=\"" << f(X(xs[base]) - 5) << "\" y=\"" << f(Y(ys[base]) - 5)
    << "\" width=\"10\" height=\"10\" fill=\"none\" stroke=\"#1f77b4\" stroke-width=\"2\"/>\n";
  s << "<text x=\"" << f(kW - kMargin) << "\" y=\"" << f(kMargin - 6)
    << "\" text-anchor=\"end\"><tspan fill=\"#d62728\">front</tspan>, <tspan "
       "fill=\"#999\">other</tspan>, "
       "<tspan fill=\"#1f77b4\">base design (square)</tspan></text>\n</svg>\n";
  return s.str();
}

std::string parallelSvg(const std::vector<Candidate>& c, const std::vector<std::size_t>& front,
                        std::size_t base, const ExploreOptions& o) {
  // Axes: parameters (the base design's own values are unknown here: it is drawn on objectives
  // only) then objectives.
  std::vector<std::string> names;
  std::vector<std::vector<double>>
      cols;  // per axis, per candidate (NaN-free: base params -> skipped)
  const std::size_t np = o.parameters.size();
  for (std::size_t p = 0; p < np; ++p) names.push_back(o.parameters[p].key);
  for (const Objective& ob : o.objectives) names.push_back(ob.label);
  std::vector<double> lo(names.size()), hi(names.size());
  for (std::size_t a = 0; a < names.size(); ++a) {
    std::vector<double> v;
    for (const Candidate& k : c) {
      if (a < np && k.params.empty()) continue;
      v.push_back(a < np ? k.params[a] : k.values[a - np]);
    }
    if (v.empty()) v.push_back(0);
    range(v, lo[a], hi[a]);
  }
  const double dx = names.size() > 1 ? (kW - 2 * kMargin) / (names.size() - 1) : 0;
  auto X = [&](std::size_t a) { return kMargin + a * dx; };
  auto Y = [&](std::size_t a, double v) {
    return kH - kMargin - (v - lo[a]) / (hi[a] - lo[a]) * (kH - 2 * kMargin);
  };
  std::ostringstream s;
  s << header("Parallel coordinates: parameters and objectives");
  for (std::size_t a = 0; a < names.size(); ++a) {
    s << "<line x1=\"" << f(X(a)) << "\" y1=\"" << f(kMargin) << "\" x2=\"" << f(X(a)) << "\" y2=\""
      << f(kH - kMargin) << "\" stroke=\"black\"/>\n";
    s << "<text x=\"" << f(X(a)) << "\" y=\"" << f(kH - kMargin + 14)
      << "\" text-anchor=\"middle\">" << esc(names[a]) << "</text>\n";
    s << "<text x=\"" << f(X(a)) << "\" y=\"" << f(kH - kMargin + 28)
      << "\" text-anchor=\"middle\">" << label(lo[a]) << "</text>\n";
    s << "<text x=\"" << f(X(a)) << "\" y=\"" << f(kMargin - 6) << "\" text-anchor=\"middle\">"
      << label(hi[a]) << "</text>\n";
  }
  auto line = [&](std::size_t i, const char* colour, double width) {
    std::string pts;
    for (std::size_t a = 0; a < names.size(); ++a) {
      if (a < np && c[i].params.empty()) continue;
      const double v = a < np ? c[i].params[a] : c[i].values[a - np];
      pts += f(X(a)) + "," + f(Y(a, v)) + " ";
    }
    s << "<polyline points=\"" << pts << "\" fill=\"none\" stroke=\"" << colour
      << "\" stroke-width=\"" << f(width) << "\"/>\n";
  };
  for (std::size_t i = 0; i < c.size(); ++i)
    if (i != base && !std::count(front.begin(), front.end(), i)) line(i, "#bbb", 0.8);
  for (std::size_t i : front) line(i, "#d62728", 1.6);
  line(base, "#1f77b4", 2.0);
  s << "</svg>\n";
  return s.str();
}

}  // namespace armstudy::explore
