#include "dexterity/png_image.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"

namespace armstudy::dexterity {

void RgbImage::set(int x, int y, std::array<std::uint8_t, 3> c) {
  const std::size_t o = (static_cast<std::size_t>(y) * width + x) * 3;
  rgb[o] = c[0];
  rgb[o + 1] = c[1];
  rgb[o + 2] = c[2];
}

namespace {

std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0) {
  static std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void put32(std::string& s, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) s.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
}

void chunk(std::string& out, const char* type, const std::string& data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  std::string td(type, 4);
  td += data;
  out += td;
  put32(out, crc32(reinterpret_cast<const std::uint8_t*>(td.data()), td.size()));
}

}  // namespace

std::string encodePng(const RgbImage& img) {
  ARMSTUDY_CHECK(img.width > 0 && img.height > 0, "encodePng: empty image");
  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  put32(ihdr, img.width);
  put32(ihdr, img.height);
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bit, RGB, deflate, filter 0, no interlace
  chunk(out, "IHDR", ihdr);
  // Raw scanlines, each prefixed by filter type 0.
  std::string raw;
  const std::size_t row = static_cast<std::size_t>(img.width) * 3;
  raw.reserve((row + 1) * img.height);
  for (int y = 0; y < img.height; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(img.rgb.data() + y * row), row);
  }
  // zlib stream with stored deflate blocks (<= 65535 bytes each) and Adler-32.
  std::string z("\x78\x01", 2);
  std::size_t pos = 0;
  do {
    const std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + len == raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(static_cast<char>(len & 0xFF));
    z.push_back(static_cast<char>(len >> 8));
    z.push_back(static_cast<char>(~len & 0xFF));
    z.push_back(static_cast<char>((~len >> 8) & 0xFF));
    z.append(raw, pos, len);
    pos += len;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  put32(z, (b << 16) | a);
  chunk(out, "IDAT", z);
  chunk(out, "IEND", "");
  return out;
}

std::array<std::uint8_t, 3> colourMap(double t) {
  // Viridis control points (t = 0, 0.25, 0.5, 0.75, 1).
  static const double cp[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  if (!std::isfinite(t)) t = 0;
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  std::array<std::uint8_t, 3> c{};
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<std::uint8_t>(std::lround(cp[i][k] + f * (cp[i + 1][k] - cp[i][k])));
  return c;
}

RgbImage heatmapImage(const std::vector<double>& values, int cols, int rows, double lo, double hi,
                      int scale) {
  ARMSTUDY_CHECK(static_cast<int>(values.size()) == cols * rows, "heatmapImage: size mismatch");
  RgbImage img(cols * scale, rows * scale);
  const double span = hi > lo ? hi - lo : 1.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double v = values[static_cast<std::size_t>(r) * cols + c];
      const std::array<std::uint8_t, 3> col =
          std::isnan(v) ? std::array<std::uint8_t, 3>{160, 160, 160} : colourMap((v - lo) / span);
      for (int dy = 0; dy < scale; ++dy)
        for (int dx = 0; dx < scale; ++dx) img.set(c * scale + dx, (rows - 1 - r) * scale + dy, col);
    }
  return img;
}

}  // namespace armstudy::dexterity
