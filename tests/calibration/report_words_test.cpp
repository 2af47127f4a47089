// The calibration reports in words: lengths beside figures in mm are written in mm (not metres to
// six decimals), and effects are named in words, not by their internal keys
// ("joint_1.viscous.viscous").
#include <catch2/catch.hpp>
#include <filesystem>
#include <regex>
#include <string>

#include "io/files.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

TEST_CASE("calibration report words: lengths in mm, effects in words, keys only in data files",
          "[calibration][study][report]") {
  const fs::path out = test::shippedOutput("arm_calibration");
  const std::regex metres(R"(\b0\.0\d{3,}\s*m\b)"), key(R"(\b(\w+)\.(\w+)\.\2\b)"),
      dotted(R"(\+(joint_offset|link_length)\.)");
  for (const fs::path& md : {out / "report.md", out / "calibration/report.md"}) {
    INFO(md.string());
    const std::string text = readFileOrThrow(md.string());
    std::smatch m;
    CHECK_FALSE(std::regex_search(text, m, metres));
    CHECK_FALSE(std::regex_search(text, m, key));
    CHECK_FALSE(std::regex_search(text, m, dotted));
    CHECK(text.find("j3 joint offset") != std::string::npos);
    CHECK(text.find(" mm") != std::string::npos);
  }
  // The data files keep the keys and SI values.
  const std::string json = readFileOrThrow((out / "calibration/tcp/result.json").string());
  CHECK(json.find("joint_offset.j3") != std::string::npos);
}
