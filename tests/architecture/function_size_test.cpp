// Functions of one screen (../shared/STYLE.md): no function body in src/ is longer than
// kMaxFunctionLines lines, counted from the line of its opening brace to the line of its closing
// brace. The scan is checked too: on a planted text it finds exactly the functions there are (free,
// member, multi-line signatures, constructors with initialisers), not the braces of strings, raw
// strings, comments, lambdas, classes, namespaces or initialiser lists.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr int kMaxFunctionLines = 120;

struct FunctionSpan {
  int first_line = 0, last_line = 0;  // of the opening and the closing brace, 1-based
  std::string head;                   // the signature, whitespace collapsed
  int lines() const { return last_line - first_line + 1; }
};

bool atLineStart(const std::string& s, std::size_t i) {
  while (i > 0 && (s[i - 1] == ' ' || s[i - 1] == '\t')) --i;
  return i == 0 || s[i - 1] == '\n';
}

// The text with preprocessor lines, comments, string and character literals (raw strings too)
// blanked out; newlines are kept, so line numbers stay.
std::string codeOnly(const std::string& s) {
  std::string out = s;
  auto blank = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to && k < out.size(); ++k)
      if (out[k] != '\n') out[k] = ' ';
  };
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '#' && atLineStart(s, i)) {  // a preprocessor line, with its continuations
      std::size_t e = i;
      while ((e = s.find('\n', e)) != std::string::npos && e > 0 && s[e - 1] == '\\') ++e;
      blank(i, e == std::string::npos ? s.size() : e);
      i = e == std::string::npos ? s.size() : e;
    } else if (s.compare(i, 2, "//") == 0) {
      const std::size_t e = s.find('\n', i);
      blank(i, e == std::string::npos ? s.size() : e);
      i = e == std::string::npos ? s.size() : e;
    } else if (s.compare(i, 2, "/*") == 0) {
      const std::size_t end = s.find("*/", i + 2);
      const std::size_t e = end == std::string::npos ? s.size() : end + 2;
      blank(i, e);
      i = e;
    } else if (s[i] == 'R' && i + 1 < s.size() && s[i + 1] == '"' &&
               (i == 0 ||
                !(std::isalnum(static_cast<unsigned char>(s[i - 1])) || s[i - 1] == '_'))) {
      const std::size_t open = s.find('(', i);
      const std::string close =
          open == std::string::npos ? "" : ")" + s.substr(i + 2, open - i - 2) + "\"";
      const std::size_t end = open == std::string::npos ? open : s.find(close, open);
      const std::size_t e = end == std::string::npos ? s.size() : end + close.size();
      blank(i + 1, e);
      i = e;
    } else if (s[i] == '"' ||
               (s[i] == '\'' &&
                !(i > 0 && std::isxdigit(static_cast<unsigned char>(s[i - 1]))))) {  // 1'000'000
      const char q = s[i];
      std::size_t e = i + 1;
      while (e < s.size() && s[e] != q) e += s[e] == '\\' ? 2 : 1;
      blank(i + 1, e);
      i = e + 1;
    } else {
      ++i;
    }
  }
  return out;
}

bool hasWord(const std::string& head, const std::string& word) {
  for (std::size_t p = head.find(word); p != std::string::npos; p = head.find(word, p + 1)) {
    const bool left =
        p == 0 || !(std::isalnum(static_cast<unsigned char>(head[p - 1])) || head[p - 1] == '_');
    const std::size_t q = p + word.size();
    const bool right =
        q >= head.size() || !(std::isalnum(static_cast<unsigned char>(head[q])) || head[q] == '_');
    if (left && right) return true;
  }
  return false;
}

enum Kind { kNamespace, kClass, kFunction, kOther };

// What a brace opens, from the text before it since the last ';', '{' or '}' (`head`), when it is
// at namespace or class scope: a namespace (or extern "C"), a class (class/struct/union/enum before
// any '(', after a template parameter list), a function (a ')' in the head, no '=' before the
// first '(', not a member's brace initialiser `name{` in a constructor's list), else an
// initialiser.
Kind classify(std::string head) {
  const std::size_t first = head.find_first_not_of(" \t\n");
  if (first == std::string::npos) return kOther;
  head = head.substr(first);
  if (head.rfind("template", 0) == 0) {  // skip `template <...>`
    int depth = 0;
    for (std::size_t k = head.find('<'); k < head.size(); ++k) {
      depth += head[k] == '<' ? 1 : head[k] == '>' ? -1 : 0;
      if (depth == 0) {
        head = head.substr(k + 1);
        break;
      }
    }
  }
  const std::string before = head.substr(0, head.find('('));
  if (hasWord(before, "namespace") || hasWord(before, "extern")) return kNamespace;
  if (hasWord(before, "class") || hasWord(before, "struct") || hasWord(before, "union") ||
      hasWord(before, "enum"))
    return kClass;
  if (head.find(')') == std::string::npos || before.find('=') != std::string::npos ||
      hasWord(before, "return"))
    return kOther;
  const std::size_t last = head.find_last_not_of(" \t\n");
  const auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  if (!ident(head[last])) return kFunction;
  std::size_t w = last;
  while (w > 0 && ident(head[w - 1])) --w;
  const std::string word = head.substr(w, last + 1 - w);
  if (word == "const" || word == "override" || word == "noexcept" || word == "final" ||
      word == "try")
    return kFunction;
  const std::size_t arrow = head.rfind("->");
  return arrow != std::string::npos && arrow > head.rfind(')') ? kFunction : kOther;
}

// Function bodies at namespace or class scope (a lambda or a local class is part of the function
// that holds it).
std::vector<FunctionSpan> functionsIn(const std::string& text) {
  struct Open {
    Kind kind;
    int line;
    std::string head;
  };
  const std::string code = codeOnly(text);
  std::vector<FunctionSpan> found;
  std::vector<Open> stack;
  std::string head;  // the text since the last ';', '{' or '}' (an initialiser's braces kept)
  int line = 1;
  const auto outer = [&] {
    return std::all_of(stack.begin(), stack.end(),
                       [](const Open& o) { return o.kind == kNamespace || o.kind == kClass; });
  };
  for (char c : code) {
    if (c == '\n') ++line;
    if (c == '{') {
      stack.push_back({outer() ? classify(head) : kOther, line, head});
      head.clear();
    } else if (c == '}') {
      if (stack.empty()) continue;
      const Open o = stack.back();
      stack.pop_back();
      head.clear();
      if (o.kind == kFunction) {
        std::string sig;
        std::istringstream words(o.head);
        for (std::string w; words >> w;) sig += (sig.empty() ? "" : " ") + w;
        found.push_back({o.line, line, sig});
      } else if (o.kind == kOther && outer()) {
        head = o.head + "{}";  // `S() : v{1}, w(2) {`: the head goes on after the initialiser
      }
    } else if (c == ';') {
      head.clear();
    } else {
      head += c;
    }
  }
  return found;
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("the function scan finds exactly the functions of a planted text", "[architecture]") {
  std::string body;
  for (int i = 0; i < 130; ++i) body += "  x += " + std::to_string(i) + ";\n";
  const std::string text =
      "#include <string>\n"                           // 1
      "namespace a {\n"                               // 2
      "struct S {\n"                                  // 3
      "  int f() const { return 1; }\n"               // 4
      "  S() : v{1}, w(2) {}\n"                       // 5
      "  int v, w;\n"                                 // 6
      "};\n"                                          // 7
      "const int table[] = {1, 2, 3};\n"              // 8
      "// int fake() {\n"                             // 9
      "int g(int a,\n"                                // 10
      "      int b) {\n"                              // 11
      "  const char* s = \"}{\";\n"                   // 12
      "  auto l = [&](int k) { return k + '}'; };\n"  // 13
      "  const char* r = R\"x(\n}\n)x\";\n"           // 14-16
      "  int x = 1'000;\n"                            // 17
      "  if (a) {\n" +                                // 18
      body +                                          // 19-148
      "  }\n"                                         // 149
      "  return x;\n"                                 // 150
      "}\n"                                           // 151
      "}  // namespace a\n";
  const std::vector<FunctionSpan> f = functionsIn(text);
  REQUIRE(f.size() == 3);
  CHECK(f[0].head == "int f() const");
  CHECK(f[0].lines() == 1);
  CHECK(f[1].head == "S() : v{}, w(2)");
  CHECK(f[2].head == "int g(int a, int b)");
  CHECK(f[2].first_line == 11);
  CHECK(f[2].last_line == 151);
  CHECK(f[2].lines() > kMaxFunctionLines);
}

TEST_CASE("no function in src/ is longer than one screen", "[architecture]") {
  const fs::path src = fs::path(ARMSTUDY_SOURCE_DIR) / "src";
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(src))
    if (e.is_regular_file() && (e.path().extension() == ".cpp" || e.path().extension() == ".hpp"))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  long functions = 0;
  int longest = 0;
  std::vector<std::string> too_long;
  for (const fs::path& p : files)
    for (const FunctionSpan& f : functionsIn(readFile(p))) {
      ++functions;
      longest = std::max(longest, f.lines());
      if (f.lines() > kMaxFunctionLines)
        too_long.push_back(fs::relative(p, src.parent_path()).generic_string() + ":" +
                           std::to_string(f.first_line) + ": " + f.head + " has " +
                           std::to_string(f.lines()) + " lines");
    }
  INFO(files.size() << " files, " << functions << " functions, the longest " << longest
                    << " lines");
  // The scan saw the tree.
  REQUIRE(files.size() > 200);
  REQUIRE(functions > 1000);
  for (const std::string& t : too_long) UNSCOPED_INFO(t);
  CHECK(too_long.empty());
}
