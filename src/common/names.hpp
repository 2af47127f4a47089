#pragma once
// The one rule for names that name files or are written into generated files (study, design,
// variant and obstacle names): not empty, letters, digits and the given punctuation only, and not
// dots alone ("." and ".." are folders).
#include <cctype>
#include <string>

namespace armstudy {

inline bool isPlainName(const std::string& s, const std::string& punctuation) {
  if (s.empty() || s.find_first_not_of('.') == std::string::npos) return false;
  for (const char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || punctuation.find(c) != std::string::npos))
      return false;
  return true;
}

// Design names: these characters besides letters and digits. Variant names add '+' and '='
// ("final_prototype_7dof+base.y=-0.1").
inline constexpr const char* kDesignNamePunctuation = "_-.";
inline constexpr const char* kVariantNamePunctuation = "_-.+=";

}  // namespace armstudy
