// The URDF's XML before urdfdom reads it (io/urdf_internal.hpp): the tag structure, the element
// lines, the numbers URDF defines and the tree shape.
#include <tinyxml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <locale>
#include <map>
#include <set>
#include <sstream>

#include "common/errors.hpp"
#include "io/units.hpp"
#include "io/urdf_internal.hpp"

namespace armstudy {
namespace urdf_detail {

namespace {

// The end of the markup starting at text[i] ('<'), one past its '>', or npos when unterminated;
// quoted attribute values may hold '>'.
std::size_t markupEnd(const std::string& text, std::size_t i) {
  for (const auto& [open, close] :
       {std::pair<const char*, const char*>{"<!--", "-->"}, {"<![CDATA[", "]]>"}, {"<?", "?>"}})
    if (text.compare(i, std::strlen(open), open) == 0) {
      const std::size_t e = text.find(close, i + std::strlen(open));
      return e == std::string::npos ? e : e + std::strlen(close);
    }
  char quote = 0;
  for (std::size_t j = i + 1; j < text.size(); ++j) {
    const char c = text[j];
    if (quote) {
      if (c == quote) quote = 0;
    } else if ((c == '"' || c == '\'') && text[i + 1] != '!') {
      quote = c;
    } else if (c == '>') {
      return j + 1;
    }
  }
  return std::string::npos;
}

}  // namespace

// Scans the tags of `text`. Elements nested more than defaults::kMaxXmlNesting deep are an
// InputError at the line of the first too deep one: the XML parsers recurse once per level, and a
// file of 60,000 nested elements would overflow the stack.
XmlTagScan scanXmlTags(const std::string& text, const std::string& file) {
  XmlTagScan out;
  std::vector<std::pair<std::string, int>> open;  // element name, line
  int line = 1;                                   // the line at text[i]
  std::size_t i = 0;
  auto problem = [&](int at) {
    if (!out.problem_line) out.problem_line = at;
  };
  auto lines = [&](std::size_t a, std::size_t b) {
    return static_cast<int>(
        std::count(text.begin() + static_cast<long>(a), text.begin() + static_cast<long>(b), '\n'));
  };
  for (std::size_t lt; (lt = text.find('<', i)) != std::string::npos;) {
    const std::size_t end = markupEnd(text, lt);
    const std::size_t stop = end == std::string::npos ? text.size() : end;
    const int tag_line = line + lines(i, lt);
    line = tag_line + lines(lt, stop);
    i = stop;
    if (end == std::string::npos) {
      problem(tag_line);
      break;
    }
    if (text[lt + 1] == '!' || text[lt + 1] == '?') continue;
    const bool closing = text[lt + 1] == '/';
    const std::size_t name_at = lt + (closing ? 2 : 1);
    const std::size_t name_end = text.find_first_of(" \t\r\n/>", name_at);
    const std::string name = text.substr(name_at, name_end - name_at);
    const unsigned char first = name.empty() ? 0 : static_cast<unsigned char>(name[0]);
    if (!(std::isalpha(first) || first == '_' || first == ':' || first >= 0x80))
      problem(tag_line);  // no element name: a stray '<'
    if (closing) {
      if (open.empty() || open.back().first != name) problem(tag_line);
      if (!open.empty()) open.pop_back();
    } else if (text[end - 2] != '/') {
      open.emplace_back(name, tag_line);
      if (open.size() > static_cast<std::size_t>(defaults::kMaxXmlNesting))
        throw InputError(file, tag_line, "xml",
                         "elements nested more than " + std::to_string(defaults::kMaxXmlNesting) +
                             " deep (<" + name + "> here; a robot description needs a few)");
    }
  }
  if (!open.empty()) problem(open.back().second);
  return out;
}

}  // namespace urdf_detail

namespace urdf_detail {
namespace {

std::string elementLabel(const TiXmlElement* e) {
  const char* name = e->Attribute("name");
  return std::string(e->Value()) + (name ? " '" + std::string(name) + "'" : std::string());
}

// Where URDF defines numbers: element paths below <joint> and <link>, with their numeric
// attributes. Other elements (vendor extensions such as <verbose>, <selfCollide>) are not URDF's
// and are ignored, as urdfdom does.
using NumberSchema = std::vector<std::pair<const char*, std::vector<const char*>>>;
const NumberSchema kJointNumbers = {
    {"origin", {"xyz", "rpy"}},
    {"axis", {"xyz"}},
    {"limit", {"lower", "upper", "effort", "velocity"}},
    {"dynamics", {"damping", "friction"}},
    {"mimic", {"multiplier", "offset"}},
    {"calibration", {"rising", "falling"}},
    {"safety_controller", {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}}};
const NumberSchema kLinkNumbers = {{"inertial/origin", {"xyz", "rpy"}},
                                   {"inertial/mass", {"value"}},
                                   {"inertial/inertia", {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}},
                                   {"visual/origin", {"xyz", "rpy"}},
                                   {"visual/geometry/box", {"size"}},
                                   {"visual/geometry/cylinder", {"radius", "length"}},
                                   {"visual/geometry/sphere", {"radius"}},
                                   {"visual/geometry/mesh", {"scale"}},
                                   {"collision/origin", {"xyz", "rpy"}},
                                   {"collision/geometry/box", {"size"}},
                                   {"collision/geometry/cylinder", {"radius", "length"}},
                                   {"collision/geometry/sphere", {"radius"}},
                                   {"collision/geometry/mesh", {"scale"}}};

// The dimension whose plausible magnitude (io/units.hpp) bounds a URDF attribute: lengths and
// positions (limits of prismatic joints too: both bounds are 1e3), angles, velocities; nullptr for
// plain numbers (masses, inertias, efforts, scales, gains).
const Dimension* attributeDimension(const std::string& attr) {
  static const Dimension length = Dimension::Length, angle = Dimension::Angle,
                         velocity = Dimension::AngularVelocity;
  static const std::set<std::string> lengths = {
      "xyz",   "size",  "radius",           "length",           "rising",
      "lower", "upper", "soft_lower_limit", "soft_upper_limit", "falling"};
  if (lengths.count(attr)) return &length;
  if (attr == "rpy") return &angle;
  if (attr == "velocity") return &velocity;
  return nullptr;
}

// Every number of attribute `attr` of element `e` must be finite and plausible: report the element
// and its line.
void checkAttribute(const TiXmlElement* e, const char* attr, const std::string& owner,
                    const std::string& file) {
  const char* v = e->Attribute(attr);
  if (!v) return;
  std::istringstream in(v);
  in.imbue(std::locale::classic());
  std::string tok;
  while (in >> tok) {
    std::string problem;
    try {
      std::size_t used = 0;
      const double d = std::stod(tok, &used);
      if (used != tok.size() || !std::isfinite(d))
        problem = "'" + tok + "' is not a finite number";
      else if (const std::string p = implausible(d, attributeDimension(attr)); !p.empty())
        problem = "'" + tok + "': " + p;
    } catch (const std::exception&) {
      problem = "'" + tok + "' is not a finite number";
    }
    if (!problem.empty())
      throw InputError(file, e->Row(), owner + "/" + e->Value() + "@" + attr, problem);
  }
}

// The elements at `path` ("a/b/c") below `e`, each checked for the attributes `attrs`.
void checkAt(const TiXmlElement* e, const std::string& path, const std::vector<const char*>& attrs,
             const std::string& owner, const std::string& file) {
  const auto slash = path.find('/');
  const std::string head = path.substr(0, slash);
  for (const TiXmlElement* c = e->FirstChildElement(head.c_str()); c;
       c = c->NextSiblingElement(head.c_str())) {
    if (slash != std::string::npos) {
      checkAt(c, path.substr(slash + 1), attrs, owner, file);
      continue;
    }
    for (const char* a : attrs) checkAttribute(c, a, owner, file);
  }
}

void checkNumbers(const TiXmlElement* e, const NumberSchema& schema, const std::string& owner,
                  const std::string& file) {
  for (const auto& [path, attrs] : schema) checkAt(e, path, attrs, owner, file);
}

// Joints whose <limit> lacks lower or upper (URDF reads them as 0).
bool limitWithoutBounds(const TiXmlElement* joint) {
  const TiXmlElement* l = joint->FirstChildElement("limit");
  return l && (!l->Attribute("lower") || !l->Attribute("upper"));
}

}  // namespace

XmlIndex indexAndCheck(const std::string& text, const std::string& file) {
  const XmlTagScan tags = scanXmlTags(text, file);
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  if (doc.Error()) {
    // TinyXML gives no row for some errors (a comment never closed, say) and a later one for
    // others (a stray '<'): the earlier of its row and the scan's line.
    int line = doc.ErrorRow() > 0 ? doc.ErrorRow() : 1;
    if (tags.problem_line > 0 && (doc.ErrorRow() <= 0 || tags.problem_line < line))
      line = tags.problem_line;
    throw InputError(file, line, "xml", std::string("not well-formed XML: ") + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(file, 1, "robot", "no <robot> element: not a URDF file");
  XmlIndex out;
  out.robot_line = robot->Row();
  struct {
    std::map<std::string, const TiXmlElement*> links, joints;
  } idx;
  static const std::set<std::string> kTypes = {"revolute", "continuous", "prismatic",
                                               "fixed",    "floating",   "planar"};
  for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Value();
    if (tag != "link" && tag != "joint") continue;
    const char* name = e->Attribute("name");
    if (!name) throw InputError(file, e->Row(), tag, "<" + tag + "> without a name");
    auto& map = tag == "link" ? idx.links : idx.joints;
    if (map.count(name))
      throw InputError(file, e->Row(), elementLabel(e), tag + " name '" + name + "' is used twice");
    map[name] = e;
  }
  for (const auto& [name, e] : idx.joints) {
    const std::string label = elementLabel(e);
    const char* type = e->Attribute("type");
    if (!type || !kTypes.count(type))
      throw InputError(file, e->Row(), label + "@type",
                       "unknown joint type '" + std::string(type ? type : "") +
                           "' (URDF: revolute, continuous, prismatic, fixed, floating, planar)");
    for (const char* role : {"parent", "child"}) {
      const TiXmlElement* r = e->FirstChildElement(role);
      const char* link = r ? r->Attribute("link") : nullptr;
      if (!link)
        throw InputError(file, e->Row(), label + "/" + role,
                         std::string("joint has no <") + role + " link=...>");
      if (!idx.links.count(link))
        throw InputError(file, r->Row(), label + "/" + role,
                         std::string(role) + " link '" + link + "' is not defined in this file");
    }
    checkNumbers(e, kJointNumbers, label, file);
    // urdfdom refuses these too, without saying what to write.
    if ((std::string(type) == "revolute" || std::string(type) == "prismatic") &&
        !e->FirstChildElement("limit"))
      throw InputError(file, e->Row(), label + "/limit",
                       "a " + std::string(type) +
                           " joint needs <limit lower=\"..\" upper=\"..\" effort=\"..\" "
                           "velocity=\"..\"/> (URDF); add it, or make a revolute joint without "
                           "stops type=\"continuous\"");
    if (limitWithoutBounds(e)) out.joints_without_bounds.insert(name);
  }
  for (const auto& [name, e] : idx.links) checkNumbers(e, kLinkNumbers, elementLabel(e), file);
  // Each link has at most one parent joint; following parents from any link must reach a root.
  std::map<std::string, std::string> parent_of;  // child link -> joint
  for (const auto& [name, e] : idx.joints) {
    const std::string child = e->FirstChildElement("child")->Attribute("link");
    if (parent_of.count(child))
      throw InputError(file, e->Row(), elementLabel(e),
                       "link '" + child + "' has two parent joints ('" + parent_of[child] +
                           "' and '" + name + "'): a URDF is a tree");
    parent_of[child] = name;
  }
  for (const auto& [link, joint] : parent_of) {
    std::set<std::string> seen{link};
    std::string cur = link;
    while (parent_of.count(cur)) {
      const TiXmlElement* j = idx.joints.at(parent_of[cur]);
      cur = j->FirstChildElement("parent")->Attribute("link");
      if (!seen.insert(cur).second)
        throw InputError(file, j->Row(), elementLabel(j),
                         "the joints form a cycle through link '" + cur + "'");
    }
  }
  for (const auto& [name, e] : idx.links) out.links[name] = e->Row();
  for (const auto& [name, e] : idx.joints) out.joints[name] = e->Row();
  return out;  // the document dies here: keep lines, not elements
}

}  // namespace urdf_detail
}  // namespace armstudy
