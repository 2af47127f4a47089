#!/usr/bin/env python3
"""Numbers the docs quote, checked against the shipped studies' outputs.

Each entry names a doc, a text with {} placeholders and, per placeholder, where its value comes from
in a study's summary.json and how it is printed. The check renders each text from the outputs and
fails when the doc does not contain it verbatim (the doc then quotes a number the study no longer
gives). Used by tests/study/doc_numbers_test.cpp, which runs the studies first.

    python3 scripts/doc_numbers.py --outputs output          # check against output/<study>/
    python3 scripts/doc_numbers.py --studies                 # the studies the entries need
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def pct(x):
    return "%.1f" % (100 * x)


def fixed(n):
    return lambda x: ("%." + str(n) + "f") % x


def grid(s, name):
    return next(g for g in s["reach"]["grids"] if g["name"] == name)


def design(s, grid_name, design_name):
    return next(d for d in grid(s, grid_name)["designs"] if d["design"] == design_name)


def orientation(s, grid_name, design_name, k):
    return design(s, grid_name, design_name)["per_orientation"][k]


def compare_row(d):
    """The compare_designs table row of design d (docs/reachability.md, "Comparing the designs")."""
    return ("| " + d + " | {} % | {} / {} / {} % | {} ({}, {}) | {} % |",
            [("compare_designs", lambda s: design(s, "canopy_wall", d)["fraction"], pct)] +
            [("compare_designs", (lambda k: lambda s: orientation(s, "canopy_wall", d, k)["fraction"])(k), pct)
             for k in range(3)] +
            [("compare_designs", lambda s: design(s, "canopy_wall", d)["manipulability"]["mean"], fixed(3)),
             ("compare_designs", lambda s: design(s, "canopy_wall", d)["manipulability"]["translation_mean"], fixed(3)),
             ("compare_designs", lambda s: design(s, "canopy_wall", d)["manipulability"]["rotation_mean"], fixed(2)),
             ("compare_designs", lambda s: design(s, "workspace_position", d)["fraction"], pct)])


def ur5_pair(s):
    return next(p for p in grid(s, "fig3_8")["comparison"]["dexterity"]
                if p["a"] == "first_prototype_6dof" and p["b"] == "ur5")


ENTRIES = [
    ("docs/reachability.md",) + compare_row("first_prototype_6dof"),
    ("docs/reachability.md",) + compare_row("first_prototype_9dof"),
    ("docs/reachability.md",
     "`studies/spraying_row.toml` reports: Fig. 3.8 grid {} % reachable collision-free at each spray",
     [("spraying_row", lambda s: design(s, "fig3_8", "first_prototype_6dof")["fraction"], pct)]),
    ("docs/reachability.md",
     "enclosing volumes); the alpha = gamma = 0 box {} % collision-free plus {} % only in collision.",
     [("spraying_row", lambda s: design(s, "coverage_alpha0_gamma0", "first_prototype_6dof")["fraction"], pct),
      ("spraying_row", lambda s: design(s, "coverage_alpha0_gamma0", "first_prototype_6dof")["status_counts"]
       ["self_collision"] / design(s, "coverage_alpha0_gamma0", "first_prototype_6dof")["poses"], pct)]),
    ("docs/reachability.md",
     "Manipulability on these grids (tool-axis rows, mean over the reachable poses): {} on Fig. 3.8",
     [("spraying_row", lambda s: design(s, "fig3_8", "first_prototype_6dof")["manipulability"]["mean"], fixed(3))]),
    ("docs/design-format.md",
     "first prototype {} % of the poses reachable",
     [("ur5_vs_first_prototype", lambda s: design(s, "fig3_8", "first_prototype_6dof")["fraction"], pct)]),
    ("docs/design-format.md",
     "manipulability {} (prototype) against {} (UR5), translational part {} against {} m^3, rotational part {} "
     "against {}",
     [("ur5_vs_first_prototype", lambda s: ur5_pair(s)["manipulability_mean"][0], fixed(3)),
      ("ur5_vs_first_prototype", lambda s: ur5_pair(s)["manipulability_mean"][1], fixed(3)),
      ("ur5_vs_first_prototype", lambda s: ur5_pair(s)["translation_mean"][0], fixed(3)),
      ("ur5_vs_first_prototype", lambda s: ur5_pair(s)["translation_mean"][1], fixed(3)),
      ("ur5_vs_first_prototype", lambda s: ur5_pair(s)["rotation_mean"][0], fixed(2)),
      ("ur5_vs_first_prototype", lambda s: ur5_pair(s)["rotation_mean"][1], fixed(2))]),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--outputs", help="folder holding <study>/summary.json of the shipped studies")
    ap.add_argument("--studies", action="store_true", help="print the studies the entries need and exit")
    a = ap.parse_args()
    studies = sorted({src for _, _, values in ENTRIES for src, _, _ in values})
    if a.studies or not a.outputs:
        print(" ".join(studies))
        return 0
    summaries = {s: json.load(open(os.path.join(a.outputs, s, "summary.json"))) for s in studies}
    failed = 0
    for doc, text, values in ENTRIES:
        rendered = text.format(*[fmt(get(summaries[src])) for src, get, fmt in values])
        if rendered not in open(os.path.join(ROOT, doc)).read():
            print("%s: the outputs give \"%s\", which the doc does not quote" % (doc, rendered))
            failed += 1
    print("%d of %d quoted texts match the outputs" % (len(ENTRIES) - failed, len(ENTRIES)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
