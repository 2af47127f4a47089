#include "io/variant.hpp"

#include <cstdio>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/names.hpp"
#include "io/design_io.hpp"
#include "model/geometry_follows.hpp"

namespace armstudy {

std::string variantName(const std::string& base, const Overrides& overrides) {
  std::string s = base;
  for (const auto& [key, value] : overrides) {
    std::string k = key.rfind("joint.", 0) == 0 ? key.substr(6) : key;
    s += "+" + k + "=" + formatG(value, 6);
  }
  return s;
}

void checkVariantName(const std::string& base, const Overrides& overrides, const std::string& file,
                      int line) {
  const std::string name = variantName(base, overrides);
  if (isPlainName(name, kVariantNamePunctuation)) return;
  std::string key = "of";  // the base's name, unless an override's part is what is not plain
  for (const auto& [k, value] : overrides)
    if (!isPlainName(variantName("v", {{k, value}}), kVariantNamePunctuation)) {
      key = k;
      break;
    }
  throw InputError(file, line, key,
                   "the variant's name would not be a plain name (it names files): joints set or "
                   "swept in a variant need names of letters, digits, '_', '-' and '.' only");
}

Model deriveVariant(const Model& base, const Overrides& overrides, const std::string& file,
                    int line, VariantGeometry geometry) {
  checkVariantName(base.name, overrides, file, line);
  Model m = base;
  for (const auto& [key, value] : overrides) {
    std::string err;
    if (!setModelEntry(m, key, value, err)) throw InputError(file, line, key, err);
  }
  m.name = variantName(base.name, overrides);
  if (geometry == VariantGeometry::Follows) followLinkGeometry(base, m);
  m.finalize();
  validateModel(m, file + " (variant '" + m.name + "')");
  return m;
}

}  // namespace armstudy
