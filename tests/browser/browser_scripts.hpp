#pragma once
// The scripts tests/browser/report_html_test.cpp adds to the pages it loads in Chromium: each
// writes what it found as JSON into a <pre> element; the pages load as frames of a harness page,
// to which each relays its findings, and the test reads them from the harness's DOM after load
// (--dump-dom). Words in capitals are replaced by the test's constants before use.

namespace armstudy::test::browser {

// clang-format off
// Collects errors from the first moment: uncaught exceptions, failed resources, console.error.
inline const char* kHeadScript = R"(<script>
window.__armstudyErrors = [];
window.addEventListener('error', e => {
  const t = e.target;
  window.__armstudyErrors.push(t && t !== window ? 'failed to load ' + (t.src || t.href || t.tagName).slice(0, 120)
                                                 : String(e.message));
}, true);
window.addEventListener('unhandledrejection', e => window.__armstudyErrors.push(String(e.reason)));
const __armstudyConsoleError = console.error;
console.error = (...a) => { window.__armstudyErrors.push(a.join(' ')); __armstudyConsoleError(...a); };
</script>)";

// After load: broken images, figures whose content sticks out, captions, page width.
inline const char* kBodyScript = R"(<script>
window.addEventListener('load', () => {
  const r = {errors: window.__armstudyErrors, broken: [], overflow: [], uncaptioned: [], noalt: [],
             figures: 0, images: document.images.length, pageOverflow: false};
  for (const img of document.images) {
    if (!(img.complete && img.naturalWidth > 0 && img.naturalHeight > 0)) r.broken.push((img.alt || img.src).slice(0, 120));
    if (!img.alt.trim()) r.noalt.push(img.src.slice(0, 120));
  }
  for (const f of document.querySelectorAll('figure')) {
    r.figures++;
    const fr = f.getBoundingClientRect();
    const name = (f.querySelector('img') || {}).alt || 'figure ' + r.figures;
    if (f.scrollWidth > f.clientWidth + 1) r.overflow.push(name + ': content wider than the figure');
    for (const e of f.querySelectorAll('*')) {
      const b = e.getBoundingClientRect();
      if (b.width > 0 && (b.right > fr.right + 1 || b.left < fr.left - 1))
        r.overflow.push(name + ': <' + e.tagName.toLowerCase() + '> leaves the figure');
    }
    const c = f.querySelector('figcaption');
    if (!c || !c.textContent.trim()) r.uncaptioned.push(name);
  }
  r.pageOverflow = document.documentElement.scrollWidth > window.innerWidth + 1;
  r.window = window.innerWidth;
  // A click on the first figure shows it across the window, a second click puts it back.
  const f0 = document.querySelector('figure img');
  if (f0) {
    const before = f0.getBoundingClientRect().width;
    f0.click();
    const zoomed = f0.getBoundingClientRect().width;
    f0.click();
    r.zoom = {before: before, zoomed: zoomed, after: f0.getBoundingClientRect().width,
              window: window.innerWidth};
  }
  const a = document.getElementById('answer');
  r.answerTop = a ? a.getBoundingClientRect().top + window.scrollY : -1;
  r.answer = a ? a.textContent : '';
  // The first screen: the words wholly inside the top FIRST_SCREEN px of a window the laptop's
  // width (what shows before any scrolling), in reading order; '|' where hidden words break a run.
  const H = FIRST_SCREEN, words = [], range = document.createRange();
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    const el = n.parentElement;
    if (!el || el.closest('script, style, pre#armstudy-check')) continue;
    if (el.getBoundingClientRect().top + window.scrollY >= H) continue;
    for (const m of n.textContent.matchAll(/\S+/g)) {
      range.setStart(n, m.index);
      range.setEnd(n, m.index + m[0].length);
      const b = range.getBoundingClientRect();
      if (b.width <= 0) continue;
      const seen = b.top + window.scrollY >= 0 && b.bottom + window.scrollY <= H && b.left >= 0 &&
                   b.right <= window.innerWidth;
      if (seen) words.push(m[0]); else if (words[words.length - 1] !== '|') words.push('|');
    }
  }
  r.firstScreen = words.join(' ');
  const li = a ? a.querySelector('li') : null;
  r.firstAnswer = li ? li.textContent.replace(/\s+/g, ' ').trim() : '';
  // Each image as drawn (in a figure or a table): its share of its own width and its right edge.
  r.drawn = [];
  for (const img of document.images)
    if (img.naturalWidth > 0)
      r.drawn.push({name: (img.alt || img.src).slice(0, 120), scale: img.getBoundingClientRect().width / img.naturalWidth,
                     right: img.getBoundingClientRect().right});
  const p = document.createElement('pre');
  p.id = 'armstudy-check';
  p.hidden = true;  // out of the screenshot taken in the same run
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";

// The 3-D view after load: script errors, the test hook, the pixels of the canvas whose colour
// differs from its corner's (the background), and the pixels that changed after a turn of 0.8 rad
// about the vertical axis.
inline const char* kViewScript = R"(<script>
window.addEventListener('load', () => {
  const r = {errors: window.__armstudyErrors, hook: !!window.armstudyView, pixels: 0, ink: 0, changed: 0};
  const cv = document.getElementById('view');
  const snap = () => {
    const c = document.createElement('canvas');
    c.width = cv.width;
    c.height = cv.height;
    const x = c.getContext('2d');
    x.drawImage(cv, 0, 0);
    return x.getImageData(0, 0, c.width, c.height).data;
  };
  if (cv && window.armstudyView && cv.width > 0 && cv.height > 0) {
    const a = snap();
    r.pixels = a.length / 4;
    for (let i = 0; i < a.length; i += 4)  // a blank canvas is one colour (black or white)
      if (Math.abs(a[i] - a[0]) + Math.abs(a[i + 1] - a[1]) + Math.abs(a[i + 2] - a[2]) > 24) ++r.ink;
    r.parts = window.armstudyView.parts();  // axes, ground, column, scale bar, framing
    const k = window.armstudyView.valued();
    r.readout = k < 0 ? null : window.armstudyView.readoutOf(k);
    window.armstudyView.rotate(0.8);
    const b = snap();
    for (let i = 0; i < a.length; i += 4)
      if (a[i] !== b[i] || a[i + 1] !== b[i + 1] || a[i + 2] !== b[i + 2]) ++r.changed;
  }
  const p = document.createElement('pre');
  p.id = 'armstudy-check';
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";

// Every SVG figure of a page with svgHolders (each inline in a <div class="armstudy-svg"
// data-file="...">), measured by Chromium's own text layout: each <text> element's box from
// getBoundingClientRect() in the SVG's user units (viewBox, else width/height). A box that leaves
// the canvas, or two boxes of one figure that overlap by more than TOLERANCE px both across and
// along, is a fault; so is a title (the plotting module's TITLE_SIZE px text) of more than
// TITLE_LINES lines. Writes <pre id="armstudy-svg-check">.
inline const char* kSvgScript = R"(<script>
window.addEventListener('load', () => {
  const tol = TOLERANCE;
  const r = {files: 0, figures: 0, texts: 0, faults: []};
  const f1 = v => v.toFixed(1);
  for (const holder of document.querySelectorAll('div.armstudy-svg')) {
    r.files++;
    const name = holder.dataset.file, svg = holder.querySelector('svg');
    if (!svg) { r.faults.push(name + ': no <svg> element'); continue; }
    r.figures++;
    const sr = svg.getBoundingClientRect();
    const vb = svg.viewBox.baseVal && svg.viewBox.baseVal.width > 0 ? svg.viewBox.baseVal : null;
    const W = vb ? vb.width : svg.width.baseVal.value, H = vb ? vb.height : svg.height.baseVal.value;
    const ox = vb ? vb.x : 0, oy = vb ? vb.y : 0, sx = W / sr.width, sy = H / sr.height;
    const boxes = [];
    let title = 0;
    for (const t of svg.querySelectorAll('text')) title += t.getAttribute('font-size') === 'TITLE_SIZE';
    if (title > TITLE_LINES) r.faults.push(name + ': a title of ' + title + ' lines');
    for (const t of svg.querySelectorAll('text')) {
      const s = t.textContent.trim(), b = t.getBoundingClientRect();
      if (!s || (b.width === 0 && b.height === 0)) continue;
      const k = {s: s.slice(0, 60), x0: ox + (b.left - sr.left) * sx, y0: oy + (b.top - sr.top) * sy,
                 x1: ox + (b.right - sr.left) * sx, y1: oy + (b.bottom - sr.top) * sy};
      boxes.push(k);
      r.texts++;
      if (k.x0 < ox - tol || k.y0 < oy - tol || k.x1 > ox + W + tol || k.y1 > oy + H + tol)
        r.faults.push(name + ": '" + k.s + "' [" + f1(k.x0) + ", " + f1(k.y0) + " .. " + f1(k.x1) + ", " +
                      f1(k.y1) + "] leaves the canvas " + f1(W) + " x " + f1(H));
    }
    for (let i = 0; i < boxes.length; ++i)
      for (let j = i + 1; j < boxes.length; ++j) {
        const a = boxes[i], b = boxes[j];
        const w = Math.min(a.x1, b.x1) - Math.max(a.x0, b.x0), h = Math.min(a.y1, b.y1) - Math.max(a.y0, b.y0);
        if (w > tol && h > tol)
          r.faults.push(name + ": '" + a.s + "' overlaps '" + b.s + "' by " + f1(w) + " x " + f1(h) + " px");
      }
  }
  const p = document.createElement('pre');
  p.id = 'armstudy-svg-check';
  p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});
</script>)";
// Added last to every page runChecks loads in a frame: after load (after the check scripts, whose
// load listeners come first) it sends what they wrote to the harness page, with the frame's name.
inline const char* kRelayScript = R"(<script>
window.addEventListener('load', () => {
  const text = id => { const p = document.getElementById(id); return p ? p.textContent : null; };
  parent.postMessage({frame: window.name, check: text('armstudy-check'), svg: text('armstudy-svg-check')}, '*');
});
</script>)";

// The harness page's: what each frame relays, by the frame's name, as JSON in
// <pre id="armstudy-frames"> (hidden: out of the screenshot taken in the same run).
inline const char* kHarnessScript = R"(<script>
const found = {};
window.addEventListener('message', e => {
  found[e.data.frame] = {check: e.data.check, svg: e.data.svg};
  let p = document.getElementById('armstudy-frames');
  if (!p) {
    p = document.createElement('pre');
    p.id = 'armstudy-frames';
    p.hidden = true;
    document.body.appendChild(p);
  }
  p.textContent = JSON.stringify(found);
});
</script>)";
// clang-format on

}  // namespace armstudy::test::browser
