#!/usr/bin/env python3
"""Load time of each study's report.html in headless Chromium (docs/performance.md "Report pages").

For every report.html under an output folder (default: output/), loads a copy with a small script
added that prints the page's own navigation timing (performance.getEntriesByType('navigation'):
DOMContentLoaded and the load event, in ms from the start of the navigation) once the load event
has fired, three times, and prints a table with the page's size and the median times, plus the
wall time of the whole browser process as a peer (start-up included). Nothing is asserted: the
numbers are a record, not a test.

    python3 tests/benchmarks/report_load_bench.py [OUTPUT_FOLDER] [RUNS]
"""
import html
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

PROBE = """<script>
addEventListener('load', () => setTimeout(() => {
  const n = performance.getEntriesByType('navigation')[0];
  const pre = document.createElement('pre');
  pre.id = 'armstudy-load';
  pre.textContent = JSON.stringify({dom: n.domContentLoadedEventEnd, load: n.loadEventEnd,
                                    images: document.images.length});
  document.body.appendChild(pre);
}, 0));
</script>"""


def load_once(page, profile):
    """Loads `page` once; returns (dom ms, load ms, images, process wall s)."""
    text = open(page, encoding="utf-8").read()
    at = text.rfind("</body>")
    if at < 0:
        raise SystemExit(f"{page}: no </body>")
    copy = os.path.join(os.path.dirname(page), "report_load_bench.html")
    with open(copy, "w", encoding="utf-8") as f:
        f.write(text[:at] + PROBE + text[at:])
    try:
        t0 = time.monotonic()
        out = subprocess.run(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + profile,
             "--window-size=1400,900", "--dump-dom", "file://" + os.path.abspath(copy)],
            capture_output=True, text=True, timeout=180).stdout
        wall = time.monotonic() - t0
    finally:
        os.remove(copy)
    start = out.find('<pre id="armstudy-load">')
    if start < 0:
        raise SystemExit(f"{page}: the page reported no load timing")
    body = out[start + len('<pre id="armstudy-load">'):out.find("</pre>", start)]
    r = json.loads(html.unescape(body))
    return r["dom"], r["load"], r["images"], wall


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "output"
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    pages = sorted(os.path.join(d, "report.html") for d, _, files in os.walk(root)
                   if "report.html" in files)
    if not pages:
        raise SystemExit(f"no report.html under {root}: run the studies first")
    print(f"| report | size [MB] | images | DOMContentLoaded [ms] | load event [ms] |"
          f" browser process [s] |\n|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as profile:
        for page in pages:
            rows = [load_once(page, profile) for _ in range(runs)]
            med = [statistics.median(r[k] for r in rows) for k in range(4)]
            print(f"| {os.path.relpath(page, root)} | {os.path.getsize(page) / 1e6:.2f} |"
                  f" {rows[0][2]} | {med[0]:.0f} | {med[1]:.0f} | {med[3]:.2f} |")


if __name__ == "__main__":
    main()
