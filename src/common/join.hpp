#pragma once
// The one way lists of words become one text ("j1, j2, j3").
#include <string>
#include <string_view>
#include <vector>

namespace armstudy {

// The items one after another, `sep` before each item once the text so far is not empty.
inline std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string s;
  for (const std::string& x : items) {
    if (!s.empty()) s += sep;
    s += x;
  }
  return s;
}

}  // namespace armstudy
