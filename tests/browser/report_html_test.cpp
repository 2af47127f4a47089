// Every shipped study's report.html in a real browser (headless Chromium, Debian `chromium`): runs
// a quick copy of each study (coarser grids, smaller audits) through the CLI, loads its report with
// a small check script added, and fails on a console error, a broken image, an element overflowing
// its figure, a figure without caption or a page wider than a laptop screen. Saves a screenshot of
// each report beside it. The 3-D view (view.html) of studies with maps loads with WebGL in
// software (SwiftShader) and must draw a non-blank canvas that changes when the view is turned.
// Every SVG figure a study writes is loaded too, and Chromium's own text layout (not the plotting
// module's measurement) must find no two text boxes of a figure overlapping and none off its
// canvas.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "common/escape.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

constexpr int kLaptopWidth = 1366, kLaptopHeight = 900;  // [px] window the reports must fit
constexpr int kPhoneWidth = 420;                         // [px] a phone's window, held upright
constexpr int kScreenshotHeight = 2400;                  // [px] screenshot of the report's top

// Collects errors from the first moment: uncaught exceptions, failed resources, console.error.
const char* kHeadScript = R"(<script>
window.__armstudyErrors = [];
window.addEventListener('error', e => {
  const t = e.target;
  window.__armstudyErrors.push(t && t !== window ? 'failed to load ' + (t.src || t.href || t.tagName).slice(0, 120)
                                                 : String(e.message));
}, true);
window.addEventListener('unhandledrejection', e => window.__armstudyErrors.push(String(e.reason)));
const __armstudyConsoleError = console.error;
console.error = (...a) => { window.__armstudyErrors.push(a.join(' ')); __armstudyConsoleError(...a); };
</script>)";

// After load: broken images, figures whose content sticks out, captions, page width.
const char* kBodyScript = R"(<script>
window.addEventListener('load', () => {
  const r = {errors: window.__armstudyErrors, broken: [], overflow: [], uncaptioned: [], noalt: [],
             figures: 0, images: document.images.length, pageOverflow: false};
  for (const img of document.images) {
    if (!(img.complete && img.naturalWidth > 0 && img.naturalHeight > 0)) r.broken.push((img.alt || img.src).slice(0, 120));
    if (!img.alt.trim()) r.noalt.push(img.src.slice(0, 120));
  }
  for (const f of document.querySelectorAll('figure')) {
    r.figures++;
    const fr = f.getBoundingClientRect();
    const name = (f.querySelector('img') || {}).alt || 'figure ' + r.figures;
    if (f.scrollWidth > f.clientWidth + 1) r.overflow.push(name + ': content wider than the figure');
    for (const e of f.querySelectorAll('*')) {
      const b = e.getBoundingClientRect();
      if (b.width > 0 && (b.right > fr.right + 1 || b.left < fr.left - 1))
        r.overflow.push(name + ': <' + e.tagName.toLowerCase() + '> leaves the figure');
    }
    const c = f.querySelector('figcaption');
    if (!c || !c.textContent.trim()) r.uncaptioned.push(name);
  }
  r.pageOverflow = document.documentElement.scrollWidth > window.innerWidth + 1;
  r.window = window.innerWidth;
  // A click on the first figure shows it across the window, a second click puts it back.
  const f0 = document.querySelector('figure img');
  if (f0) {
    const before = f0.getBoundingClientRect().width;
    f0.click();
    const zoomed = f0.getBoundingClientRect().width;
    f0.click();
    r.zoom = {before: before, zoomed: zoomed, after: f0.getBoundingClientRect().width,
              window: window.innerWidth};
  }
  const a = document.getElementById('answer');
  r.answerTop = a ? a.getBoundingClientRect().top + window.scrollY : -1;
  r.answer = a ? a.textContent : '';
  const p = document.createElement('pre');
  p.id = 'armstudy-check';
  p.hidden = true;  // out of the screenshot taken in the same run
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";

// The 3-D view after load: script errors, the test hook, the pixels of the canvas whose colour
// differs from its corner's (the background), and the pixels that changed after a turn of 0.8 rad
// about the vertical axis.
const char* kViewScript = R"(<script>
window.addEventListener('load', () => {
  const r = {errors: window.__armstudyErrors, hook: !!window.armstudyView, pixels: 0, ink: 0, changed: 0};
  const cv = document.getElementById('view');
  const snap = () => {
    const c = document.createElement('canvas');
    c.width = cv.width;
    c.height = cv.height;
    const x = c.getContext('2d');
    x.drawImage(cv, 0, 0);
    return x.getImageData(0, 0, c.width, c.height).data;
  };
  if (cv && window.armstudyView && cv.width > 0 && cv.height > 0) {
    const a = snap();
    r.pixels = a.length / 4;
    for (let i = 0; i < a.length; i += 4)  // a blank canvas is one colour (black or white)
      if (Math.abs(a[i] - a[0]) + Math.abs(a[i + 1] - a[1]) + Math.abs(a[i + 2] - a[2]) > 24) ++r.ink;
    r.parts = window.armstudyView.parts();  // axes, ground, column, scale bar, framing
    const k = window.armstudyView.valued();
    r.readout = k < 0 ? null : window.armstudyView.readoutOf(k);
    window.armstudyView.rotate(0.8);
    const b = snap();
    for (let i = 0; i < a.length; i += 4)
      if (a[i] !== b[i] || a[i + 1] !== b[i + 1] || a[i + 2] !== b[i + 2]) ++r.changed;
  }
  const p = document.createElement('pre');
  p.id = 'armstudy-check';
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";

// Every SVG figure of a page built by svgFiguresPage (each inline in a <div class="armstudy-svg"
// data-file="...">), measured by Chromium's own text layout: each <text> element's box from
// getBoundingClientRect() in the SVG's user units (viewBox, else width/height). A box that leaves
// the canvas, or two boxes of one figure that overlap by more than TOLERANCE px both across and
// along, is a fault.
const char* kSvgScript = R"(<script>
window.addEventListener('load', () => {
  const tol = TOLERANCE;
  const r = {files: 0, figures: 0, texts: 0, faults: []};
  const f1 = v => v.toFixed(1);
  for (const holder of document.querySelectorAll('div.armstudy-svg')) {
    r.files++;
    const name = holder.dataset.file, svg = holder.querySelector('svg');
    if (!svg) { r.faults.push(name + ': no <svg> element'); continue; }
    r.figures++;
    const sr = svg.getBoundingClientRect();
    const vb = svg.viewBox.baseVal && svg.viewBox.baseVal.width > 0 ? svg.viewBox.baseVal : null;
    const W = vb ? vb.width : svg.width.baseVal.value, H = vb ? vb.height : svg.height.baseVal.value;
    const ox = vb ? vb.x : 0, oy = vb ? vb.y : 0, sx = W / sr.width, sy = H / sr.height;
    const boxes = [];
    for (const t of svg.querySelectorAll('text')) {
      const s = t.textContent.trim(), b = t.getBoundingClientRect();
      if (!s || (b.width === 0 && b.height === 0)) continue;
      const k = {s: s.slice(0, 60), x0: ox + (b.left - sr.left) * sx, y0: oy + (b.top - sr.top) * sy,
                 x1: ox + (b.right - sr.left) * sx, y1: oy + (b.bottom - sr.top) * sy};
      boxes.push(k);
      r.texts++;
      if (k.x0 < ox - tol || k.y0 < oy - tol || k.x1 > ox + W + tol || k.y1 > oy + H + tol)
        r.faults.push(name + ": '" + k.s + "' [" + f1(k.x0) + ", " + f1(k.y0) + " .. " + f1(k.x1) + ", " +
                      f1(k.y1) + "] leaves the canvas " + f1(W) + " x " + f1(H));
    }
    for (let i = 0; i < boxes.length; ++i)
      for (let j = i + 1; j < boxes.length; ++j) {
        const a = boxes[i], b = boxes[j];
        const w = Math.min(a.x1, b.x1) - Math.max(a.x0, b.x0), h = Math.min(a.y1, b.y1) - Math.max(a.y0, b.y0);
        if (w > tol && h > tol)
          r.faults.push(name + ": '" + a.s + "' overlaps '" + b.s + "' by " + f1(w) + " x " + f1(h) + " px");
      }
  }
  const p = document.createElement('pre');
  p.id = 'armstudy-check';
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";

// [px] overlap of two text boxes, across and along, that is not a fault: Chromium's boxes are the
// font's ascent and descent rounded to whole pixels (up to 0.6 px taller than cairo's, which the
// layout uses), so boxes the layout sets edge to edge may share a fraction of a pixel.
constexpr double kTextTolerance_px = 1;

// Shares of the canvas [1] a rendered view must cover, and must change when turned.
constexpr double kMinInkShare = 0.005, kMinChangedShare = 0.005;

struct Check {
  nlohmann::json result;  // what the script found; null when the browser gave nothing
  std::string log;
};

std::string chromium(const fs::path& profile, int width = kLaptopWidth) {
  return "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" +
         profile.string() + " --window-size=" + std::to_string(width) + ",";
}

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

// Loads the page `file` in Chromium (extra command-line `flags`) and returns what its check script
// wrote into <pre id="armstudy-check"> (the DOM after load, --dump-dom). With a `screenshot` path,
// the same run also saves the window's pixels there, the window kScreenshotHeight px tall (no check
// depends on the window's height: the answer's place is measured from the top of the page).
Check runCheck(const fs::path& file, const fs::path& work, int width, const std::string& flags,
               const fs::path& screenshot = {}) {
  Check c;
  const int height = screenshot.empty() ? kLaptopHeight : kScreenshotHeight;
  const std::string shot = screenshot.empty() ? "" : " --screenshot=" + screenshot.string();
  runCommand("timeout 120 " + chromium(work / "profile", width) + std::to_string(height) + flags +
                 shot + " --virtual-time-budget=10000 --dump-dom file://" + file.string(),
             c.log);
  const std::size_t id = c.log.find("<pre id=\"armstudy-check\"");  // then attributes, '>'
  const std::size_t a = id == std::string::npos ? id : c.log.find('>', id);
  const std::size_t b = a == std::string::npos ? a : c.log.find("</pre>", a);
  if (b != std::string::npos)
    c.result = nlohmann::json::parse(unescapeText(c.log.substr(a + 1, b - a - 1)));
  return c;
}

// Loads `page` with `script` before </body> and kHeadScript (a copy is written beside it) and
// returns the findings.
Check checkWith(const fs::path& page, const fs::path& work, const char* script, int width,
                const std::string& flags, const fs::path& screenshot = {}) {
  std::string html = readFileOrThrow(page.string());
  const std::size_t head = html.find("<head>"), body = html.rfind("</body>");
  REQUIRE(head != std::string::npos);
  REQUIRE(body != std::string::npos);
  html.insert(body, script);
  html.insert(head + 6, kHeadScript);
  const fs::path copy = page.parent_path() / (page.stem().string() + "_browser_check.html");
  writeFileAtomic(copy.string(), html);
  Check c = runCheck(copy, work, width, flags, screenshot);
  fs::remove(copy);
  return c;
}

// Loads a report page with kBodyScript and returns the findings; with a `screenshot` path, saves a
// screenshot of the page there in the same run.
Check checkPage(const fs::path& page, const fs::path& work, int width = kLaptopWidth,
                const fs::path& screenshot = {}) {
  return checkWith(page, work, kBodyScript, width, "", screenshot);
}

// Loads a view.html with WebGL in software (SwiftShader) and returns what kViewScript found.
Check checkView(const fs::path& page, const fs::path& work) {
  return checkWith(page, work, kViewScript, kLaptopWidth,
                   " --use-angle=swiftshader --enable-unsafe-swiftshader");
}

// The 3-D view of a study with maps in `dir`: it exists (three.js was found and inlined), is light,
// report.html links it, and it draws a non-blank canvas that changes when turned.
void requireView(const fs::path& dir, const fs::path& work) {
  REQUIRE(fs::exists(dir / "view.html"));
  CHECK(fs::file_size(dir / "view.html") < 5u * 1024 * 1024);
  CHECK(readFileOrThrow((dir / "report.html").string()).find("href=\"view.html\"") !=
        std::string::npos);
  const Check c = checkView(dir / "view.html", work);
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

// Every .svg file under `dir` (sorted) inline in one page `page`, each in a <div
// class="armstudy-svg" data-file="<path under dir>">, with kSvgScript; returns the number of files.
std::size_t svgFiguresPage(const fs::path& dir, const fs::path& page) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".svg") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::string html =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>body{margin:0} "
      "div.armstudy-svg svg{display:block}</style></head><body>\n";
  for (const fs::path& f : files) {
    std::string svg = readFileOrThrow(f.string());
    if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find("?>") + 2);  // the XML prolog
    html += "<div class=\"armstudy-svg\" data-file=\"" + xmlEscape(fs::relative(f, dir).string()) +
            "\">" + svg + "</div>\n";
  }
  std::string script = kSvgScript;
  script.replace(script.find("TOLERANCE"), 9, std::to_string(kTextTolerance_px));
  writeFileAtomic(page.string(), html + script + "</body></html>\n");
  return files.size();
}

// The text faults of every SVG figure under `dir` as Chromium lays them out ("" = none); `files`:
// how many SVG files there were, `texts`: how many text boxes the browser measured.
std::string svgFigureFaults(const fs::path& dir, const fs::path& work, std::size_t& files,
                            int& texts) {
  const fs::path page = work / "svg_figures.html";
  files = svgFiguresPage(dir, page);
  const Check c = runCheck(page, work, kLaptopWidth, "");
  fs::remove(page);
  texts = 0;
  if (c.result.is_null()) return "the browser returned no check result:\n" + c.log.substr(0, 2000);
  texts = c.result.value("texts", 0);
  std::string f;
  if (c.result.value("figures", 0) != static_cast<int>(files))
    f += std::to_string(c.result.value("figures", 0)) + " SVG figures of " + std::to_string(files) +
         " loaded\n";
  for (const auto& e : c.result["faults"]) f += e.get<std::string>() + "\n";
  return f;
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
  const Check c = checkPage(page, work);
  REQUIRE_FALSE(c.result.is_null());
  CHECK(c.result["broken"].size() >= 1);
  CHECK(c.result["overflow"].size() >= 1);
  CHECK(c.result["uncaptioned"].size() == 1);
  CHECK(c.result["noalt"].size() == 1);
  bool boom = false;
  for (const auto& e : c.result["errors"]) boom = boom || e.get<std::string>() == "boom";
  CHECK(boom);
  fs::remove_all(work);
}

TEST_CASE(
    "the browser's SVG text check finds overprinted labels and text off the canvas, and passes a "
    "clean figure",
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
  std::size_t files = 0;
  int texts = 0;
  const std::string f = svgFigureFaults(figs, work, files, texts);
  INFO(f);
  CHECK(files == 3);
  CHECK(texts == 6);
  CHECK(f.find("sub/overlap.svg: 'stem map coverage' overlaps 'fruits feasible'") !=
        std::string::npos);
  CHECK(f.find("offcanvas.svg: 'stem map manipulability'") != std::string::npos);
  CHECK(f.find("offcanvas.svg: 'reads upwards past the top'") != std::string::npos);
  CHECK(f.find("clean.svg") == std::string::npos);
  std::istringstream lines(f);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) ++n;
  CHECK(n == 3);
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
      // Every SVG figure the study wrote, as Chromium lays out its text: no overlap, none off the
      // canvas.
      {
        std::size_t files = 0;
        int texts = 0;
        const std::string f = svgFigureFaults(report.parent_path(), work, files, texts);
        INFO(study.filename().string() + ": SVG figures: " + f);
        CHECK(f.empty());
        if (files > 0) CHECK(texts > 0);
      }
      // The report as a laptop shows it, with a screenshot kept beside the report.
      const fs::path shot = report.parent_path() / "report_screenshot.png";
      const Check c = checkPage(report, work, kLaptopWidth, shot);
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
      const Check phone = checkPage(report, work, kPhoneWidth);
      INFO(study.filename().string() + " at " << kPhoneWidth << " px: " + faults(phone));
      CHECK(faults(phone).empty());
      // A study with reach grids or stem maps (an exploration's too, where it writes one) has its
      // 3-D view.
      const std::string text = readFileOrThrow(study.string());
      if (((text.find("\n[[reach.grid]]") != std::string::npos ||
            text.find("\n[dexterity]") != std::string::npos) &&
           text.find("\n[explore") == std::string::npos) ||
          fs::exists(report.parent_path() / "view.html")) {
        INFO(study.filename().string() + ": the 3-D view");
        requireView(report.parent_path(), work);
      }
    }
  }
  fs::remove_all(work);
}
