#!/usr/bin/env python3
"""Prints the index of thesis equations cited in src/ (docs/architecture.md, "Equation index").

Usage: python3 scripts/equation_index.py   (from the repository root; prints Markdown)
A citation is "eq. 5.10", "eq. (5.10)", "Eq. 5.10", "eqs. 5.4-5.6", "equation 3.30" or a bare
"(5.10)" in a comment. The function is found by a heuristic: for a comment starting in column 0,
the declaration that follows it (a function name, else "near <its first characters>"); for any
other line, the enclosing definition (the last function signature above starting in column 0);
"(file header)" when there is none.
"""
import os
import re
import sys

NUM = r"[A-C1-9]\.\d+[a-z]?"
CITE = re.compile(r"\b[Ee]q(?:uation)?s?\.?\s*((?:\(?" + NUM + r"\)?(?:\s*(?:,|and|-|–|to|/)\s*)?)+)")
BARE = re.compile(r"(?<![\w.])\((" + NUM + r")\)")
NUMBER = re.compile(NUM)
KEYWORDS = {"if", "for", "while", "switch", "return", "catch", "sizeof", "static_assert", "decltype",
            "defined", "else", "do", "using", "namespace", "struct", "class", "enum", "TEST_CASE"}
SIGNATURE = re.compile(r"^(?:template\s*<[^>]*>\s*)?(?:[\w:<>,\*&\s]+?[\s\*&])?(~?[A-Za-z_]\w*(?:::~?\w+)*)\s*\(")


def function_name(line):
    s = line.strip()
    if not s or s.startswith(("//", "#", "*", "}", "{", "return", "else")) or s.endswith(";") and "{" not in s:
        # Declarations in headers end with ';' and count as signatures when they look like one.
        if not (s.endswith(";") and "(" in s and not s.startswith(("//", "#", "return"))):
            return None
    if "=" in s.split("(")[0]:
        return None
    m = SIGNATURE.match(s)
    if not m:
        return None
    name = m.group(1)
    if name.split("::")[-1] in KEYWORDS or name in KEYWORDS:
        return None
    head = s[: m.start(1)].strip()
    if not head and "::" not in name:
        return None  # a call statement such as `foo(x);`, not a signature
    return name


def comment_of(line):
    i = line.find("//")
    return line[i:] if i >= 0 else None


def citations(line):
    comment = comment_of(line)
    found = []
    for m in CITE.finditer(line):
        found += NUMBER.findall(m.group(1))
    if comment:
        for m in BARE.finditer(comment):
            found.append(m.group(1))
    seen = []
    for n in found:
        if n not in seen:
            seen.append(n)
    return seen


def main():
    rows = []
    for root, _, files in os.walk("src"):
        for fn in sorted(files):
            if not fn.endswith((".hpp", ".cpp", ".h", ".in")):
                continue
            path = os.path.join(root, fn)
            lines = open(path, encoding="utf-8", errors="replace").read().split("\n")
            for i, line in enumerate(lines):
                eqs = citations(line)
                if not eqs:
                    continue
                func = None
                is_comment = line.startswith("//")  # a column-0 comment documents what follows
                if is_comment:
                    for j in range(i + 1, min(len(lines), i + 26)):
                        nxt = lines[j].strip()
                        if not nxt or nxt.startswith("//"):
                            continue
                        func = function_name(lines[j])
                        if func is None and not nxt.startswith(("#", "namespace", "}")):
                            func = "near " + nxt[:50].replace("|", "\\|")
                        break
                if func is None:
                    for j in range(i, -1, -1):
                        if lines[j][:1] in (" ", "\t") or lines[j].rstrip().endswith(";"):
                            continue  # definitions start in column 0 in this code base
                        func = function_name(lines[j])
                        if func:
                            break
                for e in eqs:
                    rows.append((e, path, i + 1, func or "(file header)"))

    def key(r):
        ch, num = r[0].split(".")
        return (ch.isalpha(), ch, int(re.match(r"\d+", num).group()), num, r[1], r[2])

    rows.sort(key=key)
    print("| Equation | File:line | Function |")
    print("|---|---|---|")
    for e, path, line, func in rows:
        print(f"| {e} | `{path}:{line}` | `{func}` |")
    print(f"\n{len(rows)} citations of {len({r[0] for r in rows})} equations.", file=sys.stderr)


if __name__ == "__main__":
    main()
