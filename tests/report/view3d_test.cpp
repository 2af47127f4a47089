// The 3-D view's page (report/view3d): its data read back independently of the writer (the JSON
// parsed with nlohmann, the base64 arrays decoded by tests/view_page.hpp) gives the points,
// statuses and levels put in; maps beyond kViewMaxPoints are thinned to every k-th point; a name
// holding "</script>" does not end the data early; the bytes are the same on a second call.
#include "report/view3d.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>

#include "view_page.hpp"

using namespace armstudy::report;

namespace {

constexpr double kPositionQuantum = armstudy::test::kViewPositionQuantum;  // [m]
using armstudy::test::unbase64;
nlohmann::json pageData(const std::string& html) { return armstudy::test::viewPageData(html); }

}  // namespace

TEST_CASE("view.html carries the maps' points, thinned beyond the cap, and reads back",
          "[report]") {
  View3d v;
  v.title = "3-D view: test";
  v.value_label = "manipulability";
  ViewCloud c;
  c.name = "grid </script><b>x</b>: design";
  c.status_names = {"reachable", "", "", "", "only in self-collision"};
  const long n = 2 * kViewMaxPoints + 7;
  for (long i = 0; i < n; ++i) {
    c.p_W.push_back({0.001 * (i % 1000) - 0.3, 0.5, 0.002 * (i / 1000)});
    c.status.push_back(i % 5 == 0 ? 1 : (i % 2 ? 4 : 0));  // status 1 is not drawn
    c.value.push_back(i % 2 ? NAN : 0.5 * (i % 7) / 6);
  }
  c.arm_W = {{0, 0, 0}, {0, 0, 0.5}, {0.2, 0.3, 0.9}};
  v.clouds.push_back(c);
  v.solids.push_back({"stem", 2, {{{0.2, 0.7, 0}, {0.2, 0.7, 2}, {0, 0, 0}}}, 0.012});
  const std::string html = viewHtml(v, "<script>/* three.js */</script>\n");
  CHECK(html == viewHtml(v, "<script>/* three.js */</script>\n"));
  const nlohmann::json d = pageData(html);
  REQUIRE(d["clouds"].size() == 1);
  const auto& jc = d["clouds"][0];
  CHECK(jc["name"] == c.name);
  // The drawn points (status 0 or 4) in index order, every stride-th of them.
  std::vector<long> drawn;
  for (long i = 0; i < n; ++i)
    if (c.status[i] != 1) drawn.push_back(i);
  const long stride = d["stride"].get<long>();
  CHECK(stride == (static_cast<long>(drawn.size()) + kViewMaxPoints - 1) / kViewMaxPoints);
  const std::string pos = unbase64(jc["pos"]), st = unbase64(jc["status"]),
                    lv = unbase64(jc["level"]);
  const std::size_t kept = st.size();
  CHECK(kept == (drawn.size() + stride - 1) / stride);
  CHECK(static_cast<long>(kept) <= kViewMaxPoints);
  REQUIRE(pos.size() == 12 * kept);
  REQUIRE(lv.size() == kept);
  const std::string val = unbase64(jc["value"]);
  REQUIRE(val.size() == 4 * kept);
  const double hi = std::stod(jc["hi"].get<std::string>());
  CHECK(hi == Approx(0.5));
  for (std::size_t k = 0; k < kept; k += 997) {
    const long i = drawn[k * stride];
    for (int a = 0; a < 3; ++a) {
      std::uint32_t u = 0;
      for (int b = 0; b < 4; ++b)
        u |= static_cast<std::uint32_t>(static_cast<unsigned char>(pos[12 * k + 4 * a + b]))
             << (8 * b);
      CHECK(static_cast<std::int32_t>(u) * kPositionQuantum ==
            Approx(c.p_W[i][a]).margin(kPositionQuantum));
    }
    CHECK(static_cast<int>(static_cast<unsigned char>(st[k])) == c.status[i]);
    const int level = static_cast<unsigned char>(lv[k]);
    if (std::isnan(c.value[i]))
      CHECK(level == 255);
    else
      CHECK(level == std::lround(254 * c.value[i] / hi));
    // The value itself (float32, for the pointer's read-out).
    std::uint32_t u = 0;
    for (int b = 0; b < 4; ++b)
      u |= static_cast<std::uint32_t>(static_cast<unsigned char>(val[4 * k + b])) << (8 * b);
    float f = 0;
    std::memcpy(&f, &u, sizeof f);
    if (std::isnan(c.value[i]))
      CHECK(std::isnan(f));
    else
      CHECK(f == static_cast<float>(c.value[i]));
  }
  CHECK(d["solids"][0]["name"] == "stem");
  CHECK(d["clouds"][0]["arm"].size() == 3);
}

TEST_CASE("view.html keeps user strings as data: no end tag and no comment opener in its JSON",
          "[report][hardening]") {
  View3d v;
  v.title = "3-D view: </title><script>alert(1)</script>";
  v.value_label = "manipulability";
  ViewCloud c;
  // A joint or design name: "<!--" then "<script>" would keep the data element open past its
  // "</script>" (the HTML parser's escaped script state), running what follows.
  const std::string hostile = "j2<!--<script>\"</script><!-- x --></SCRIPT>\\u2028";
  c.name = hostile;
  c.arm_caption = hostile;
  c.status_names = {hostile};
  c.p_W = {{0, 0, 0}};
  c.status = {0};
  c.value = {0.5};
  c.arm_W = {{0, 0, 0}, {0, 0, 0.5}};
  v.clouds.push_back(c);
  v.solids.push_back({hostile, 1, {{{0.2, 0.7, 0}, {0, 0, 0}, {0, 0, 0}}}, 0.012});
  const std::string html = viewHtml(v, "");
  const std::string open = "<script type=\"application/json\" id=\"armstudy-view-data\">";
  const std::size_t a = html.find(open) + open.size(), b = html.find("</script>", a);
  REQUIRE(b != std::string::npos);
  std::string data = html.substr(a, b - a);
  for (char& ch : data) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  CHECK(data.find("<!") == std::string::npos);
  CHECK(data.find("</") == std::string::npos);
  const nlohmann::json d = pageData(html);  // the strings read back as they were
  CHECK(d["clouds"][0]["name"] == hostile);
  CHECK(d["clouds"][0]["arm_caption"] == hostile);
  CHECK(d["clouds"][0]["status_names"][0] == hostile);
  CHECK(d["solids"][0]["name"] == hostile);
  CHECK(html.find("<title>3-D view: &lt;/title&gt;&lt;script&gt;") != std::string::npos);
}

TEST_CASE(
    "view.html gives each measure its own colour scale: maps share one only when they show "
    "the same quantity in the same unit",
    "[report]") {
  View3d v;
  v.title = "3-D view: scales";
  v.value_label = "manipulability";
  const auto cloud = [](const std::string& quantity, double value) {
    ViewCloud c;
    c.name = quantity;
    c.value_quantity = quantity;
    c.status_names = {"reachable"};
    c.p_W = {{0, 0, 0}, {0.1, 0, 0}};
    c.status = {0, 0};
    c.value = {value, 0.5 * value};
    return c;
  };
  // Spraying (5 task rows) and position (3 rows) manipulabilities: both in m^3, not comparable.
  v.clouds = {cloud("5 rows", 0.2), cloud("3 rows", 0.9), cloud("5 rows", 0.4)};
  const nlohmann::json d = pageData(viewHtml(v, ""));
  const auto hi = [&](int i) { return std::stod(d["clouds"][i]["hi"].get<std::string>()); };
  CHECK(hi(0) == Approx(0.4));
  CHECK(hi(2) == Approx(0.4));
  CHECK(hi(1) == Approx(0.9));
  CHECK(d["clouds"][1]["quantity"] == "3 rows");
}
