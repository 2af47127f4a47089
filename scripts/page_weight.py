#!/usr/bin/env python3
"""Page weight of every HTML page under an output folder, counted as
tests/report/page_weight_test.cpp counts it: the page, each file of the folder it loads (src=) and
each figure it links (href= to .svg/.png/.jpg/.gif/.webp); linked data files (CSV, JSON, VTK, a
design) are downloads the reader asks for and are listed apart, not counted.

    python3 scripts/page_weight.py output/            # every study run into output/
"""
import os
import re
import sys

FIGURES = (".svg", ".png", ".jpg", ".jpeg", ".gif", ".webp")


def weight(page, root):
    folder = os.path.dirname(page)
    html = open(page, encoding="utf-8", errors="replace").read()
    counted, data, seen = os.path.getsize(page), 0, set()
    for attr in (' src="', ' href="'):
        for m in re.finditer(re.escape(attr) + r'([^"]{0,4096})', html):
            target = re.split(r"[#?]", m.group(1))[0]
            if not target or "://" in target or target.startswith("data:"):
                continue
            f = os.path.realpath(os.path.join(folder, target))
            if (f.endswith(".html") or not os.path.isfile(f) or f in seen
                    or not f.startswith(os.path.realpath(root) + os.sep)):
                continue
            seen.add(f)
            if attr == ' src="' or f.lower().endswith(FIGURES):
                counted += os.path.getsize(f)
            else:
                data += os.path.getsize(f)
    return counted, data


def main(root):
    print("| page | counted [MB] | own bytes [MB] | linked data, not counted [MB] |")
    print("|---|---:|---:|---:|")
    for folder, _, files in sorted(os.walk(root)):
        for name in sorted(files):
            if name.endswith(".html"):
                page = os.path.join(folder, name)
                counted, data = weight(page, root)
                print(f"| {os.path.relpath(page, root)} | {counted / 1e6:.2f} | "
                      f"{os.path.getsize(page) / 1e6:.2f} | {data / 1e6:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "output")
