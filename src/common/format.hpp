#pragma once
// The one short format of a number in reports, labels and names: printf's "%.<digits>g".
#include <cstdio>
#include <string>

namespace armstudy {

inline std::string formatG(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace armstudy
