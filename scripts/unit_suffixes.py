#!/usr/bin/env python3
"""Counts the double members of the engine's headers (src/**/*.hpp) that carry a unit suffix
(docs/architecture.md, "Names and units") and lists the names used both with and without one
(`min_distance` and `min_distance_m`).

    python3 scripts/unit_suffixes.py [--list]

A member is a `double` declared at the start of a line ending in `;` (no parameter list), in a
struct or class body or at namespace scope; function-local doubles in inline bodies count too.
"""
import collections
import pathlib
import re
import sys

# The SI units and their combinations the project writes as suffixes (docs/architecture.md).
UNITS = {
    "m", "m2", "m3", "mm", "rad", "deg", "s", "Hz", "N", "Nm", "kg", "kgm2", "A", "V", "W", "J",
    "ohm", "H", "C", "mps", "mps2", "radps", "radps2", "Aps", "NmpA", "Nms", "Nmps", "mpm",
    "rpm", "m_s", "rad_s", "rad_s2", "m_s2",
}
DECL = re.compile(r"^\s+(?:static\s+)?(?:constexpr\s+)?(?:const\s+)?double\s+([^;(]*);")


def members(root):
    for path in sorted(root.glob("**/*.hpp")):
        for line in path.read_text().splitlines():
            m = DECL.match(line.split("//")[0])
            if not m:
                continue
            for part in m.group(1).split(","):
                name = part.split("=")[0].split("{")[0].strip()
                if re.fullmatch(r"[A-Za-z_]\w*", name):
                    yield path, name


def suffix(name):
    for u in sorted(UNITS, key=len, reverse=True):
        if name.endswith("_" + u) and len(name) > len(u) + 1:
            return u
    return None


def main():
    root = pathlib.Path(__file__).resolve().parent.parent / "src"
    found = list(members(root))
    with_unit = [(p, n) for p, n in found if suffix(n)]
    names = {n for _, n in found}
    both = sorted({n for n in names if suffix(n) and n[: -len(suffix(n)) - 1] in names})
    print(f"{len(found)} double members, {len(with_unit)} with a unit suffix")
    print(f"{len(both)} names used both with and without a unit suffix")
    for n in both:
        bare = n[: -len(suffix(n)) - 1]
        where = collections.Counter(str(p.relative_to(root)) for p, m in found if m == bare)
        print(f"  {bare} / {n}: bare in {', '.join(sorted(where))}")
    if "--list" in sys.argv:
        for p, n in found:
            print(f"{p.relative_to(root)} {n} {suffix(n) or '-'}")


if __name__ == "__main__":
    main()
