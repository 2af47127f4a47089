// The design TOML text of a calibrated copy: which design a text is (shownDesign) and the line
// edit that writes one entry (setDesignEntry); declared in arm_calibration.hpp.
#include <sstream>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "common/errors.hpp"

namespace armstudy::calibration {

ShownDesign shownDesign(const std::string& text) {
  std::istringstream is(text);
  for (std::string l; std::getline(is, l);) {
    const auto end = l.find_last_not_of(" \t\r");
    const std::string mark = "   # calibrated";
    if (end != std::string::npos && end + 1 >= mark.size() &&
        l.compare(end + 1 - mark.size(), mark.size(), mark) == 0)
      return ShownDesign::calibrated_copy;
  }
  return ShownDesign::as_designed;
}

std::string setDesignEntry(const std::string& text, const std::string& header,
                           const std::string& match_key, const std::string& match_value,
                           const std::string& key, const std::string& value_text) {
  std::vector<std::string> lines;
  {
    std::istringstream is(text);
    for (std::string l; std::getline(is, l);) lines.push_back(l);
  }
  auto trim = [](const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    return b == std::string::npos ? std::string()
                                  : s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
  };
  auto isHeader = [&](const std::string& l) { return !trim(l).empty() && trim(l)[0] == '['; };
  auto headerIs = [&](const std::string& l, const std::string& h) {
    return trim(l).rfind(h, 0) == 0;
  };
  auto keyOf = [&](const std::string& l) {
    const std::string t = trim(l);
    const auto eq = t.find('=');
    return eq == std::string::npos ? std::string() : trim(t.substr(0, eq));
  };
  auto valueOf = [&](const std::string& l) {
    std::string v = trim(l.substr(l.find('=') + 1));
    const auto hash = v.find('#');
    if (hash != std::string::npos) v = trim(v.substr(0, hash));
    if (v.size() >= 2 && v.front() == '"') v = v.substr(1, v.size() - 2);
    return v;
  };
  auto blockEnd = [&](std::size_t start) {
    std::size_t e = start + 1;
    while (e < lines.size() && !isHeader(lines[e])) ++e;
    return e;
  };
  const bool friction = header == "[drive.friction]";
  const std::string outer = friction ? "[[drive]]" : header;
  std::size_t start = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!headerIs(lines[i], outer)) continue;
    bool ok = match_key.empty();
    for (std::size_t k = i + 1; k < blockEnd(i) && !ok; ++k)
      ok = keyOf(lines[k]) == match_key && valueOf(lines[k]) == match_value;
    if (ok) {
      start = i;
      break;
    }
  }
  if (start == lines.size()) {
    if (!match_key.empty())
      throw InputError(
          "", 0, key,
          "the design has no " + outer + " with " + match_key + " = \"" + match_value + "\"");
    lines.push_back("");
    lines.push_back(header);
    start = lines.size() - 1;
  }
  if (friction) {
    const std::size_t e = blockEnd(start);
    if (e < lines.size() && headerIs(lines[e], "[drive.friction]")) {
      start = e;
    } else {
      lines.insert(lines.begin() + e, "[drive.friction]");
      start = e;
    }
  }
  const std::size_t end = blockEnd(start);
  for (std::size_t k = start + 1; k < end; ++k)
    if (keyOf(lines[k]) == key) {
      lines[k] = key + " = " + value_text + "   # calibrated";
      std::string out;
      for (const auto& l : lines) out += l + "\n";
      return out;
    }
  lines.insert(lines.begin() + start + 1, key + " = " + value_text + "   # calibrated");
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

}  // namespace armstudy::calibration
