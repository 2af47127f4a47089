// Every shipped study's report.html in a real browser (headless Chromium, Debian `chromium`): runs
// a quick copy of each study (coarser grids, smaller audits) through the CLI, loads its report with
// a small check script added, and fails on a console error, a broken image, an element overflowing
// its figure, a figure without caption or a page wider than a laptop screen. Saves a screenshot of
// each report beside it. The 3-D view (view.html) of studies with maps or other spatial outputs
// loads with WebGL in software (SwiftShader) and must draw a non-blank canvas that changes when the
// view is turned.
// Every SVG figure a study writes is loaded too, and Chromium's own text layout (not the plotting
// module's measurement) must find no two text boxes of a figure overlapping and none off its
// canvas. A study's pages (the report at a laptop's and a phone's width, the 3-D view) load in one
// Chromium run, as frames of a harness page of their own sizes.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "browser/browser_scripts.hpp"
#include "common/escape.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
using namespace armstudy::test::browser;
namespace fs = std::filesystem;

namespace {

constexpr int kLaptopWidth = 1366, kLaptopHeight = 900;  // [px] window the reports must fit
// [px] a phone's window, held upright: the narrowest window headless Chromium opens, the width the
// phone check has always had (a frame can be narrower).
constexpr int kPhoneWidth = 500;
constexpr int kScreenshotHeight = 2400;  // [px] screenshot of the report's top
constexpr int kFirstScreenHeight = 768;  // [px] a laptop's window (1366 x 768) before scrolling
// Share of its own width a figure's image keeps at the laptop's width: an SVG drawn smaller than
// this has tick labels of 11 px below 5.5 px.
constexpr double kMinFigureScale = 0.5;

// [px] overlap of two text boxes, across and along, that is not a fault: Chromium's boxes are the
// font's ascent and descent rounded to whole pixels (up to 0.6 px taller than cairo's, which the
// layout uses), so boxes the layout sets edge to edge may share a fraction of a pixel.
constexpr double kTextTolerance_px = 1;

// Shares of the canvas [1] a rendered view must cover, and must change when turned.
constexpr double kMinInkShare = 0.005, kMinChangedShare = 0.005;

struct Check {
  nlohmann::json result;  // what the check script found; null when the browser gave nothing
  nlohmann::json svg;     // what kSvgScript found, where the page holds it; else null
  std::string log;
};

// [px] the plotting module's title size, and the most lines a figure's title may take.
constexpr int kTitleSize = 15, kMaxTitleLines = 2;

// The Chromium command line, a window of `width` x `height` px.
std::string chromium(const fs::path& profile, int width, int height) {
  return "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" +
         profile.string() + " --window-size=" + std::to_string(width) + "," +
         std::to_string(height);
}

// WebGL in software (SwiftShader), for the 3-D views.
const char* const kSoftwareWebGl = " --use-angle=swiftshader --enable-unsafe-swiftshader";

std::string unescapeText(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"},
                                 {"&gt;", ">"},
                                 {"&quot;", "\""},
                                 {"&amp;", "&"}}) {
    for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
      s.replace(p, from.size(), to);
  }
  return s;
}

// The JSON text of <pre id="`id`"> in an HTML text; null when there is none.
nlohmann::json preJson(const std::string& html, const std::string& id) {
  const std::size_t at = html.find("<pre id=\"" + id + "\"");  // then attributes, '>'
  const std::size_t a = at == std::string::npos ? at : html.find('>', at);
  const std::size_t b = a == std::string::npos ? a : html.find("</pre>", a);
  return b == std::string::npos
             ? nlohmann::json()
             : nlohmann::json::parse(unescapeText(html.substr(a + 1, b - a - 1)));
}

// A page to load: `page` with `script` added before </body>, in a frame of `width` x `height` px.
struct Frame {
  fs::path page;
  std::string script;
  int width = kLaptopWidth, height = kLaptopHeight;
};

// The harness page of runChecks: the frames as iframes of their own sizes, stacked at the top left
// corner with the first on top (each inside the window, so that Chromium renders every one), and
// what each frame relays (kRelayScript) collected into <pre id="armstudy-frames">.
std::string harnessPage(const std::vector<Frame>& frames, const std::vector<fs::path>& copies) {
  std::string html =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>body{margin:0}"
      "iframe{position:absolute;left:0;top:0;border:0}</style></head><body>\n" +
      std::string(kHarnessScript) + "\n";
  for (std::size_t i = 0; i < frames.size(); ++i)
    html += "<iframe name=\"" + std::to_string(i) + "\" src=\"file://" + copies[i].string() +
            "\" width=\"" + std::to_string(frames[i].width) + "\" height=\"" +
            std::to_string(frames[i].height) +
            "\" style=\"z-index:" + std::to_string(frames.size() - i) + "\"></iframe>\n";
  return html + "</body></html>\n";
}

// Loads the frames' pages in one Chromium run (extra command-line `flags`) and returns, in their
// order, what each page's check scripts wrote into <pre id="armstudy-check"> and
// <pre id="armstudy-svg-check">. A copy of each page with kHeadScript, its script and kRelayScript
// is written beside it (its relative links resolve) and removed after; the harness page
// (harnessPage) holds the copies and is read from the DOM after load (--dump-dom). With a
// `screenshot` path, the same run saves the window's pixels there: the first frame's top (no check
// depends on a frame's height: the answer's place is measured from the top of the page).
std::vector<Check> runChecks(const std::vector<Frame>& frames, const fs::path& work,
                             const std::string& flags, const fs::path& screenshot = {}) {
  std::vector<fs::path> copies;
  int width = 0, height = 0;
  for (const Frame& f : frames) {
    std::string html = readFileOrThrow(f.page.string());
    const std::size_t head = html.find("<head>"), body = html.rfind("</body>");
    REQUIRE(head != std::string::npos);
    REQUIRE(body != std::string::npos);
    html.insert(body, f.script + kRelayScript);
    html.insert(head + 6, kHeadScript);
    copies.push_back(f.page.parent_path() / (f.page.stem().string() + "_browser_check_" +
                                             std::to_string(copies.size()) + ".html"));
    writeFileAtomic(copies.back().string(), html);
    width = std::max(width, f.width), height = std::max(height, f.height);
  }
  const fs::path harness = work / "harness.html";
  writeFileAtomic(harness.string(), harnessPage(frames, copies));
  const std::string shot = screenshot.empty() ? "" : " --screenshot=" + screenshot.string();
  std::string log;
  runCommand("timeout 180 " + chromium(work / "profile", width, height) + flags + shot +
                 " --virtual-time-budget=10000 --dump-dom file://" + harness.string(),
             log);
  for (const fs::path& c : copies) fs::remove(c);
  fs::remove(harness);
  const nlohmann::json found = preJson(log, "armstudy-frames");
  std::vector<Check> checks(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    Check& c = checks[i];
    c.log = log;
    const std::string name = std::to_string(i);
    if (!found.is_object() || !found.contains(name)) continue;
    for (const auto& [key, into] :
         {std::pair<const char*, nlohmann::json*>{"check", &c.result}, {"svg", &c.svg}})
      if (found[name][key].is_string())
        *into = nlohmann::json::parse(found[name][key].get<std::string>());
  }
  return checks;
}

// kBodyScript with the first screen's height filled in.
std::string bodyScript() {
  std::string script = kBodyScript;
  for (std::size_t at = script.find("FIRST_SCREEN"); at != std::string::npos;
       at = script.find("FIRST_SCREEN", at))
    script.replace(at, 12, std::to_string(kFirstScreenHeight));
  return script;
}

// The 3-D view of a study with maps in `dir`, before it is loaded: it exists (three.js was found
// and inlined), is light, and report.html links it.
void requireViewFile(const fs::path& dir) {
  REQUIRE(fs::exists(dir / "view.html"));
  CHECK(fs::file_size(dir / "view.html") < 5u * 1024 * 1024);
  CHECK(readFileOrThrow((dir / "report.html").string()).find("href=\"view.html\"") !=
        std::string::npos);
}

// What kViewScript found in a 3-D view: it draws a non-blank canvas that changes when turned.
void requireViewDrawn(const Check& c) {
  INFO(c.log.substr(0, 2000));
  REQUIRE_FALSE(c.result.is_null());
  INFO("view check: " << c.result.dump());
  CHECK(c.result["errors"].empty());
  REQUIRE(c.result["hook"].get<bool>());
  const double pixels = c.result["pixels"].get<double>();
  REQUIRE(pixels > 0);
  CHECK(c.result["ink"].get<double>() / pixels > kMinInkShare);
  CHECK(c.result["changed"].get<double>() / pixels > kMinChangedShare);
  // The world's axes and ground, a scale bar of a round length and 40-300 px, the first camera
  // showing everything, and the pointer's read-out of a map point: its position in mm and its
  // value with the unit.
  const nlohmann::json& parts = c.result["parts"];
  CHECK(parts["axes"].get<double>() > 0);
  CHECK(parts["ground_step"].get<double>() > 0);
  CHECK(parts["framed"].get<bool>());
  CHECK(parts["scale"]["px"].get<double>() >= 40);
  CHECK(parts["scale"]["px"].get<double>() <= 300);
  const nlohmann::json& readout = c.result["readout"];
  REQUIRE(readout.is_object());
  CHECK(readout["picked"].get<std::string>().find(" mm: ") != std::string::npos);
  const std::string own = readout["own"].get<std::string>(), unit = readout["unit"];
  CHECK(own.find(" mm: ") != std::string::npos);
  CHECK(own.size() > unit.size() + 1);
  CHECK(own.compare(own.size() - unit.size() - 1, std::string::npos, " " + unit) == 0);
}

// Every .svg file under `dir` (sorted) inline, each in a <div class="armstudy-svg"
// data-file="<path under dir>">, then kSvgScript; `files`: how many. Inside a box out of sight
// (far below the page, clipped to nothing), so that a report page can carry them without a change
// to what it shows or to its width.
std::string svgHolders(const fs::path& dir, std::size_t& files) {
  std::vector<fs::path> svgs;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".svg") svgs.push_back(e.path());
  std::sort(svgs.begin(), svgs.end());
  std::string html =
      "<div style=\"position:absolute;left:0;top:100000px;width:0;height:0;overflow:hidden\">"
      "<style>div.armstudy-svg svg{display:block}</style>\n";
  for (const fs::path& f : svgs) {
    std::string svg = readFileOrThrow(f.string());
    if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find("?>") + 2);  // the XML prolog
    html += "<div class=\"armstudy-svg\" data-file=\"" + xmlEscape(fs::relative(f, dir).string()) +
            "\">" + svg + "</div>\n";
  }
  std::string script = kSvgScript;
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"TOLERANCE", std::to_string(kTextTolerance_px)},
        {"TITLE_SIZE", std::to_string(kTitleSize)},
        {"TITLE_LINES", std::to_string(kMaxTitleLines)}})
    for (std::size_t at = script.find(key); at != std::string::npos; at = script.find(key, at))
      script.replace(at, key.size(), value);
  files = svgs.size();
  return html + "</div>\n" + script;
}

// The text faults of the SVG figures a check found ("" = none); `files`: how many SVG files the
// page held, `texts`: how many text boxes the browser measured.
std::string svgFaults(const Check& c, std::size_t files, int& texts) {
  texts = 0;
  if (c.svg.is_null()) return "the browser returned no SVG check result:\n" + c.log.substr(0, 2000);
  texts = c.svg.value("texts", 0);
  std::string f;
  if (c.svg.value("figures", 0) != static_cast<int>(files))
    f += std::to_string(c.svg.value("figures", 0)) + " SVG figures of " + std::to_string(files) +
         " loaded\n";
  for (const auto& e : c.svg["faults"]) f += e.get<std::string>() + "\n";
  return f;
}

// The text faults of every SVG figure under `dir` as Chromium lays them out, on a page of their
// own ("" = none).
std::string svgFigureFaults(const fs::path& dir, const fs::path& work, std::size_t& files,
                            int& texts) {
  const fs::path page = work / "svg_figures.html";
  writeFileAtomic(page.string(),
                  "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body>\n"
                  "</body></html>\n");
  const Check c = runChecks({Frame{page, svgHolders(dir, files)}}, work, "")[0];
  fs::remove(page);
  return svgFaults(c, files, texts);
}

// Everything the check found wrong, one line each ("" = nothing).
std::string faults(const Check& c) {
  if (c.result.is_null()) return "the browser returned no check result:\n" + c.log.substr(0, 2000);
  std::string f;
  for (const char* key : {"errors", "broken", "overflow", "uncaptioned", "noalt"})
    for (const auto& e : c.result[key]) f += std::string(key) + ": " + e.get<std::string>() + "\n";
  if (c.result["pageOverflow"].get<bool>())
    f += "the page is wider than the window (" + std::to_string(c.result.value("window", 0)) +
         " px)\n";
  return f;
}

// A quick copy of a shipped study: every grid range with more than kValues values gets kValues,
// audits check a few poses from a few starts, relative paths point at the sources. The report has
// the same sections, figures and files as the real study's, only coarser.
constexpr int kValues = 5;
std::string quickStudy(const std::string& toml, const fs::path& study_dir) {
  static const std::map<std::string, double> unit = {
      {"m", 1}, {"cm", 1e-2}, {"mm", 1e-3}, {"deg", 1}, {"rad", 180 / M_PI}};
  static const std::regex range(
      R"#(((?:from|min)\s*=\s*")([-+0-9.eE]+)\s*([a-z]+)("\s*,\s*(?:to|max)\s*=\s*")([-+0-9.eE]+)\s*([a-z]+)("\s*,\s*step\s*=\s*")([-+0-9.eE]+)\s*([a-z]+)")#");
  static const std::regex audit_count(R"(^(\s*)(poses|cells)\s*=\s*\d+)"),
      audit_starts(R"(^(\s*)starts\s*=\s*\d+)");
  static const std::regex relative(R"#("((?:\.\./|data/)[^"]*)")#");
  std::istringstream in(toml);
  std::string line, out, section;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') section = line.substr(0, line.find(']') + 1);
    std::smatch m;
    if (std::regex_search(line, m, range) && unit.count(m[3]) && unit.count(m[6]) &&
        unit.count(m[9])) {
      const double a = std::stod(m[2]) * unit.at(m[3]), b = std::stod(m[5]) * unit.at(m[6]);
      const double step = std::stod(m[8]) * unit.at(m[9]);
      if (step > 0 && (b - a) / step > kValues - 1) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.9g %s", (b - a) / (kValues - 1) / unit.at(m[6]),
                      m[6].str().c_str());
        line = m.prefix().str() + m[1].str() + m[2].str() + " " + m[3].str() + m[4].str() +
               m[5].str() + " " + m[6].str() + m[7].str() + buf + "\"" + m.suffix().str();
      }
    }
    if (section.find("audit") != std::string::npos) {
      line = std::regex_replace(line, audit_count, "$1$2 = 2");
      line = std::regex_replace(line, audit_starts, "$1starts = 4");
    }
    line = std::regex_replace(line, relative, "\"" + study_dir.string() + "/$1\"");
    out += line + "\n";
  }
  return out;
}

// The value of the first `key = "..."` line of a TOML text ("" when there is none).
std::string tomlString(const std::string& toml, const std::string& key) {
  const std::regex line("(^|\n)" + key + R"re(\s*=\s*"((?:[^"\\]|\\.)*)")re");
  std::smatch m;
  return std::regex_search(toml, m, line) ? m[2].str() : "";
}

// `s` without white space: the first screen's words are joined by blanks where the page has none
// (a code span and the colon after it), so texts are compared without it.
std::string squeezed(const std::string& s) {
  std::string out;
  for (char c : s)
    if (!std::isspace(static_cast<unsigned char>(c))) out += c;
  return out;
}

// A share [1] as the reports print it: "71.4 %".
std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %%", 100 * share);
  return buf;
}

// What the first screen of the report in `dir` must hold beyond the question and the answer's
// first item, one line per miss ("" = nothing missing): the near and far halves of every stem map
// with a row (dexterity/summary.json), and every largest reach found against its reference
// (summary.json), each number with its unit.
std::string firstScreenMisses(const fs::path& dir, const std::string& first) {
  std::string miss;
  const auto need = [&](const std::string& what, const std::string& why) {
    if (squeezed(first).find(squeezed(what)) == std::string::npos)
      miss += why + ": '" + what + "'\n";
  };
  const fs::path dex = dir / "dexterity" / "summary.json";
  if (fs::exists(dex))
    for (const auto& d : nlohmann::json::parse(readFileOrThrow(dex.string()))["designs"]) {
      if (!d.contains("row_sweep") || d["row_sweep"].empty()) continue;
      const std::string design = d["design"];
      for (const char* half : {"near_half", "far_half"}) {
        const auto& h = d["status"][half];
        need(percent(h["reachable"].get<double>() / h["cells"].get<double>()), design + " " + half);
      }
      need("near half", design), need("far half", design);
    }
  const fs::path sum = dir / "summary.json";
  if (fs::exists(sum)) {
    const auto js = nlohmann::json::parse(readFileOrThrow(sum.string()));
    if (js.contains("reach"))
      for (const auto& g : js["reach"]["grids"])
        for (const auto& r : g.value("reference_reach", nlohmann::json::array())) {
          char found[32], ref[32];
          std::snprintf(found, sizeof found, "%.0f mm",
                        1e3 * r["largest_reach_found_m"].get<double>());
          std::snprintf(ref, sizeof ref, "%.0f mm", 1e3 * r["reference_reach_m"].get<double>());
          const std::string what =
              r["design"].get<std::string>() + " on grid " + g["name"].get<std::string>();
          need(found, what + ": largest reach found"), need(ref, what + ": reference");
        }
  }
  return miss;
}

// The shipped studies whose outputs are spatial but not maps, each with its 3-D view: a
// calibration's residuals over the workspace (arm_calibration, the TX40's identification), the
// harvest holding grid, the tracking runs among obstacles. Their view must exist, not only be
// checked when it does.
const std::set<std::string> kViewsWithoutMaps = {"arm_calibration.toml",
                                                 "staubli_tx40_identification.toml",
                                                 "harvest_torque.toml", "fig5_13_obstacle.toml"};

fs::path workDir() {
  const fs::path d = fs::temp_directory_path() / ("armstudy_browser_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE(
    "the browser check finds a broken image, an overflowing figure, an image without alt text and "
    "a "
    "console error",
    "[browser][report]") {
  // The check itself must be able to fail: a page with each fault.
  const fs::path work = workDir();
  const fs::path page = work / "faulty.html";
  writeFileAtomic(
      page.string(),
      "<!DOCTYPE html><html><head><style>figure{width:300px;margin:0}</style></head><body>"
      "<figure><img src=\"missing.png\" alt=\"missing\"><figcaption>a</figcaption></figure>"
      "<figure><div style=\"width:900px;height:10px\"></div><figcaption>b</figcaption></figure>"
      "<figure><img alt=\"x\" src=\"data:image/gif;base64,R0lGODlhAQABAAAAACw=\"></figure>"
      "<figure><img src=\"data:image/gif;base64,R0lGODlhAQABAAAAACw=\"><figcaption>c"
      "</figcaption></figure>"
      "<script>console.error('boom')</script></body></html>\n");
  const Check c = runChecks({Frame{page, bodyScript()}}, work, "")[0];
  REQUIRE_FALSE(c.result.is_null());
  CHECK(c.result["broken"].size() >= 1);
  CHECK(c.result["overflow"].size() >= 1);
  CHECK(c.result["uncaptioned"].size() == 1);
  CHECK(c.result["noalt"].size() == 1);
  bool boom = false;
  for (const auto& e : c.result["errors"]) boom = boom || e.get<std::string>() == "boom";
  CHECK(boom);
  // Frames of one run are windows of their own widths: a block 600 px wide makes the phone's page
  // scroll sideways, not the laptop's.
  const fs::path wide = work / "wide.html";
  writeFileAtomic(wide.string(),
                  "<!DOCTYPE html><html><head></head><body>"
                  "<div style=\"width:600px;height:10px\"></div></body></html>\n");
  const std::vector<Check> two =
      runChecks({Frame{wide, bodyScript()}, Frame{wide, bodyScript(), kPhoneWidth}}, work, "");
  REQUIRE_FALSE(two[0].result.is_null());
  REQUIRE_FALSE(two[1].result.is_null());
  CHECK(two[0].result["window"] == kLaptopWidth);
  CHECK(two[1].result["window"] == kPhoneWidth);
  CHECK_FALSE(two[0].result["pageOverflow"].get<bool>());
  CHECK(two[1].result["pageOverflow"].get<bool>());
  fs::remove_all(work);
}

TEST_CASE(
    "the browser's SVG text check finds overprinted labels, text off the canvas and a long title, "
    "and passes a clean figure",
    "[browser][report]") {
  // The check itself must be able to fail: one figure with each fault, one without.
  const fs::path work = workDir();
  const fs::path figs = work / "figures";
  fs::create_directories(figs / "sub");
  const std::string head =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
      "font-family=\"'DejaVu Sans', Verdana, sans-serif\" font-size=\"13\" ";
  writeFileAtomic((figs / "clean.svg").string(),
                  head +
                      "width=\"300\" height=\"100\" viewBox=\"0 0 300 100\">"
                      "<text x=\"10\" y=\"30\">stem map coverage</text>"
                      "<text x=\"10\" y=\"60\">fruits feasible</text></svg>\n");
  writeFileAtomic((figs / "sub" / "overlap.svg").string(),  // no viewBox: width and height
                  head +
                      "width=\"300\" height=\"100\"><text x=\"10\" y=\"30\">stem map "
                      "coverage</text><text x=\"60\" y=\"34\">fruits feasible</text></svg>\n");
  writeFileAtomic((figs / "offcanvas.svg").string(),
                  head +
                      "width=\"600\" height=\"200\" viewBox=\"0 0 300 100\">"
                      "<text x=\"250\" y=\"60\">stem map manipulability</text>"
                      "<text x=\"40\" y=\"60\" transform=\"rotate(-90 40 60)\">reads upwards "
                      "past the top</text></svg>\n");
  writeFileAtomic((figs / "title.svg").string(),  // a title of three lines
                  head +
                      "width=\"300\" height=\"100\" viewBox=\"0 0 300 100\">"
                      "<text x=\"10\" y=\"20\" font-size=\"15\">the first line</text>"
                      "<text x=\"10\" y=\"40\" font-size=\"15\">the second line</text>"
                      "<text x=\"10\" y=\"60\" font-size=\"15\">the third line</text></svg>\n");
  std::size_t files = 0;
  int texts = 0;
  const std::string f = svgFigureFaults(figs, work, files, texts);
  INFO(f);
  CHECK(files == 4);
  CHECK(texts == 9);
  CHECK(f.find("title.svg: a title of 3 lines") != std::string::npos);
  CHECK(f.find("sub/overlap.svg: 'stem map coverage' overlaps 'fruits feasible'") !=
        std::string::npos);
  CHECK(f.find("offcanvas.svg: 'stem map manipulability'") != std::string::npos);
  CHECK(f.find("offcanvas.svg: 'reads upwards past the top'") != std::string::npos);
  CHECK(f.find("clean.svg") == std::string::npos);
  std::istringstream lines(f);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) ++n;
  CHECK(n == 4);
  fs::remove_all(work);
}

TEST_CASE(
    "every shipped study's report.html loads in Chromium without errors, broken images or overflow",
    "[browser][report][cli]") {
  const fs::path work = workDir();
  const fs::path out = work / "output";
  std::vector<fs::path> studies;
  for (const auto& e : fs::directory_iterator(sourcePath("studies")))
    if (e.path().extension() == ".toml") studies.push_back(e.path());
  std::sort(studies.begin(), studies.end());
  REQUIRE(studies.size() >= 10);
  for (const fs::path& study : studies) {
    SECTION(study.filename().string()) {
      std::string log;
      const fs::path quick = work / study.filename();
      writeFileAtomic(quick.string(),
                      quickStudy(readFileOrThrow(study.string()), study.parent_path()));
      INFO(readFileOrThrow(quick.string()));
      REQUIRE(runCommand(binaryPath() + " run " + quick.string() +
                             " --overwrite --threads 2 --output " + out.string(),
                         log) == 0);
      // The study's name is its output folder; the run's report is the newest report.html.
      fs::path report;
      for (const auto& e : fs::recursive_directory_iterator(out))
        if (e.path().filename() == "report.html" &&
            (report.empty() || fs::last_write_time(e.path()) > fs::last_write_time(report)))
          report = e.path();
      REQUIRE_FALSE(report.empty());
      CHECK(fs::file_size(report) < 5u * 1024 * 1024);  // a light page
      // A study with reach grids or stem maps, or spatial outputs of another kind
      // (kViewsWithoutMaps), has its 3-D view (an exploration's too, where it writes one).
      const std::string text = readFileOrThrow(study.string());
      const bool view = ((text.find("\n[[reach.grid]]") != std::string::npos ||
                          text.find("\n[dexterity]") != std::string::npos) &&
                         text.find("\n[explore") == std::string::npos) ||
                        kViewsWithoutMaps.count(study.filename().string()) ||
                        fs::exists(report.parent_path() / "view.html");
      if (view) {
        INFO(study.filename().string() + ": the 3-D view");
        requireViewFile(report.parent_path());
      }
      // One Chromium run: the report as a laptop shows it, with a screenshot kept beside the
      // report, the page carrying every SVG figure the study wrote, out of sight, for Chromium's
      // text layout (no overlap, none off the canvas, titles of at most two lines); the report on
      // a phone; the 3-D view.
      const fs::path shot = report.parent_path() / "report_screenshot.png";
      std::size_t files = 0;
      std::vector<Frame> frames = {{report, bodyScript() + svgHolders(report.parent_path(), files),
                                    kLaptopWidth, kScreenshotHeight},
                                   {report, bodyScript(), kPhoneWidth, kLaptopHeight}};
      if (view) frames.push_back({report.parent_path() / "view.html", kViewScript});
      const std::vector<Check> checks = runChecks(frames, work, view ? kSoftwareWebGl : "", shot);
      const Check& c = checks[0];
      {
        int texts = 0;
        const std::string f = svgFaults(c, files, texts);
        INFO(study.filename().string() + ": SVG figures: " + f);
        CHECK(f.empty());
        if (files > 0) CHECK(texts > 0);
      }
      CHECK(fs::exists(shot));
      CHECK(fs::file_size(shot) > 1000);
      INFO(study.filename().string() + ": " + faults(c));
      CHECK(faults(c).empty());
      CHECK(c.result.value("figures", 0) + c.result.value("images", 0) > 0);
      if (c.result.value("figures", 0) > 0) {  // click to enlarge, click to put back
        const auto& z = c.result["zoom"];
        INFO("zoom: " << z.dump());
        REQUIRE(z.is_object());
        CHECK(z["zoomed"].get<double>() >= 0.9 * z["window"].get<double>() - 24);
        CHECK(z["after"].get<double>() == Approx(z["before"].get<double>()));
      }
      // The study's question heads the page, above the answer (every shipped study states one).
      {
        const std::string html = readFileOrThrow(report.string());
        const std::string text = readFileOrThrow(study.string());
        CHECK(text.find("\nquestion = \"") != std::string::npos);
        const std::size_t q = html.find("<strong>Question:</strong>");
        CHECK(q != std::string::npos);
        CHECK(q < html.find("</header>"));
      }
      // The first screen (1366 x 768, before any scrolling) holds the study's question and the
      // answer's first item up to its first number and unit; the halves of a stem map with its
      // row and each largest reach against its reference among them.
      {
        const std::string first = squeezed(c.result.value("firstScreen", ""));
        INFO(study.filename().string() + ": first screen: " + c.result.value("firstScreen", ""));
        const std::string question =
            squeezed(tomlString(readFileOrThrow(study.string()), "question"));
        CHECK_FALSE(question.empty());
        CHECK(first.find(question) != std::string::npos);
        // The answer's first item up to its first number and what that number counts or
        // measures ("... 71.4 %", "... 912 mm", "... 589 cells").
        const std::string item = c.result.value("firstAnswer", "");
        INFO("first item of the answer: " << item);
        std::smatch number;
        const std::regex with_unit(R"re(\b[0-9][0-9.]*\s?(%|[A-Za-z][A-Za-z^0-9]*))re");
        REQUIRE(std::regex_search(item, number, with_unit));
        const std::string lead = item.substr(0, number.position(0) + number.length(0));
        INFO("its lead: " << lead);
        CHECK(first.find(squeezed(lead)) != std::string::npos);
        CHECK(firstScreenMisses(report.parent_path(), c.result.value("firstScreen", "")) == "");
      }
      // Every image (in a figure or a table) fits the laptop's window and keeps at least
      // kMinFigureScale of its width (maps side by side wrap instead of shrinking).
      for (const auto& d : c.result["drawn"]) {
        INFO(d.dump());
        CHECK(d["scale"].get<double>() >= kMinFigureScale);
        CHECK(d["right"].get<double>() <= kLaptopWidth + 1);
      }
      // The answer opens the page: within the first 1,000 px, and it names, for every reach grid,
      // the design summary.json ranks first by reachable share, with that share as printed.
      INFO("answer block at " << c.result.value("answerTop", -1.0)
                              << " px: " << c.result.value("answer", ""));
      CHECK(c.result.value("answerTop", -1.0) >= 0);
      CHECK(c.result.value("answerTop", -1.0) < 1000);
      const fs::path summary = report.parent_path() / "summary.json";
      if (fs::exists(summary)) {
        const auto js = nlohmann::json::parse(readFileOrThrow(summary.string()));
        for (const auto& g : js["reach"]["grids"]) {
          std::string first;
          double best = -1;
          for (const auto& d : g["designs"])
            if (d["fraction"].get<double>() > best)
              best = d["fraction"].get<double>(), first = d["design"];
          char pct[32];
          std::snprintf(pct, sizeof pct, "%.1f %%", 100 * best);
          const std::string grid = "grid " + g["name"].get<std::string>();
          const std::string answer = c.result.value("answer", "");
          const std::size_t at = answer.find(grid);
          INFO(grid << ": " << first << " " << pct);
          REQUIRE(at != std::string::npos);
          const std::size_t line_start = answer.rfind("reach:", at),
                            line_end = answer.find("reach:", at);
          const std::string line = answer.substr(
              line_start, line_end == std::string::npos ? line_end : line_end - line_start);
          CHECK(line.find(first) != std::string::npos);
          CHECK(line.find(pct) != std::string::npos);
        }
      }
      // On a phone's width: no figure sticks out and the page does not scroll sideways.
      const Check& phone = checks[1];
      INFO(study.filename().string() + " at " << kPhoneWidth << " px: " + faults(phone));
      CHECK(faults(phone).empty());
      CHECK(phone.result.value("window", 0) == kPhoneWidth);
      if (view) {
        INFO(study.filename().string() + ": the 3-D view");
        requireViewDrawn(checks[2]);
      }
    }
  }
  fs::remove_all(work);
}
