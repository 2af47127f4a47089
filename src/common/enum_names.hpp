#pragma once
// Names of an enum's values, one table per enum used both ways: enumName (toString) and
// parseEnumName. names[i] names the value first + i, so the enum's values must be consecutive and
// in the table's order.
#include <cstddef>
#include <string_view>

namespace armstudy {

template <class Enum, std::size_t N>
const char* enumName(Enum e, const char* const (&names)[N], int first = 0) {
  const int i = static_cast<int>(e) - first;
  return i >= 0 && i < static_cast<int>(N) ? names[i] : "?";
}

// Sets `out` to the value named `text`; false (out unchanged) when no value has that name.
template <class Enum, std::size_t N>
bool parseEnumName(std::string_view text, const char* const (&names)[N], Enum& out, int first = 0) {
  for (std::size_t i = 0; i < N; ++i)
    if (text == names[i]) {
      out = static_cast<Enum>(first + static_cast<int>(i));
      return true;
    }
  return false;
}

}  // namespace armstudy
