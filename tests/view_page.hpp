#pragma once
// view.html's data read back independently of the writer (report/view3d.cpp): the JSON parsed with
// nlohmann, the base64 arrays decoded here into positions, statuses, levels and values.
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace armstudy::test {

inline constexpr double kViewPositionQuantum = 1e-4;  // [m] the page's position resolution

inline std::string unbase64(const std::string& s) {
  static const std::string abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  int bits = 0;
  std::uint32_t acc = 0;
  for (const char c : s) {
    if (c == '=') break;
    acc = (acc << 6) | static_cast<std::uint32_t>(abc.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((acc >> bits) & 0xff);
    }
  }
  return out;
}

inline nlohmann::json viewPageData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"armstudy-view-data\">";
  const std::size_t a = html.find(open);
  REQUIRE(a != std::string::npos);
  const std::size_t b = html.find("</script>", a);
  REQUIRE(b != std::string::npos);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

inline std::uint32_t littleEndian32(const std::string& bytes, std::size_t at) {
  std::uint32_t u = 0;
  for (int b = 0; b < 4; ++b)
    u |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + b])) << (8 * b);
  return u;
}

// One map of the page decoded: positions [m], statuses and values (float32) of its drawn points.
struct ViewMap {
  std::string name, unit, quantity, caption;
  std::vector<std::array<double, 3>> p_W, arm_W;
  std::vector<int> status;
  std::vector<float> value;
};

inline ViewMap viewMap(const nlohmann::json& c) {
  ViewMap m;
  m.name = c["name"];
  m.unit = c["unit"];
  m.quantity = c["quantity"];
  m.caption = c["arm_caption"];
  const std::string pos = unbase64(c["pos"]), st = unbase64(c["status"]),
                    val = unbase64(c["value"]);
  REQUIRE(pos.size() == 12 * st.size());
  REQUIRE(val.size() == 4 * st.size());
  for (std::size_t k = 0; k < st.size(); ++k) {
    std::array<double, 3> p{};
    for (int a = 0; a < 3; ++a)
      p[a] = static_cast<std::int32_t>(littleEndian32(pos, 12 * k + 4 * a)) * kViewPositionQuantum;
    m.p_W.push_back(p);
    m.status.push_back(static_cast<unsigned char>(st[k]));
    const std::uint32_t u = littleEndian32(val, 4 * k);
    float f = 0;
    std::memcpy(&f, &u, sizeof f);
    m.value.push_back(f);
  }
  for (const auto& p : c["arm"]) m.arm_W.push_back({p[0], p[1], p[2]});
  return m;
}

}  // namespace armstudy::test
