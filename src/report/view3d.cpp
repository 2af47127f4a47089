#include "report/view3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/format.hpp"
#include "report/html_report.hpp"  // base64, htmlEscape
#include "report/image.hpp"

namespace armstudy::report {

namespace {

// A JSON string literal that is also safe inside a <script> element: "</" and "<!" never appear
// (no end tag, no "<!--" that would change how the element's end is found).
std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      o += buf;
    } else if (c == '/' && i > 0 && s[i - 1] == '<') {
      o += "\\/";
    } else if (c == '!' && i > 0 && s[i - 1] == '<') {
      o += "\\u0021";
    } else {
      o += c;
    }
  }
  return o + "\"";
}

std::string point(const std::array<double, 3>& p) {
  return "[" + formatFixed(p[0], 4) + "," + formatFixed(p[1], 4) + "," + formatFixed(p[2], 4) + "]";
}

void putInt32(std::string& b, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int k = 0; k < 4; ++k) b += static_cast<char>((u >> (8 * k)) & 0xff);  // little-endian
}

// The colour level of a value on the shared scale 0..hi: 0..254, 255 = no value.
std::uint8_t level(double v, double hi) {
  if (std::isnan(v)) return 255;
  if (!(hi > 0)) return 0;
  return static_cast<std::uint8_t>(std::lround(std::clamp(v / hi, 0.0, 1.0) * 254));
}

// One cloud as a JSON object: the points drawn (statuses shown, every `stride`-th of them) as
// base64 arrays of positions [0.1 mm, int32], statuses and value levels [uint8].
bool drawn(const ViewCloud& c, std::size_t i) {
  const int s = c.status[i];
  return s >= 0 && s < static_cast<int>(c.status_names.size()) && !c.status_names[s].empty();
}

void putFloat32(std::string& b, double v) {
  const float f = static_cast<float>(v);
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  for (int k = 0; k < 4; ++k) b += static_cast<char>((u >> (8 * k)) & 0xff);  // little-endian
}

std::string cloudJson(const ViewCloud& c, double hi, long stride, long& shown) {
  std::string pos, st, lv, val;
  long kept = 0;
  for (std::size_t i = 0; i < c.p_W.size(); ++i) {
    const int s = c.status[i];
    if (!drawn(c, i)) continue;
    if (kept++ % stride != 0) continue;
    for (double x : c.p_W[i]) putInt32(pos, static_cast<std::int32_t>(std::lround(x * 1e4)));
    st += static_cast<char>(s);
    lv += static_cast<char>(level(c.value[i], hi));
    putFloat32(val, c.value[i]);
    ++shown;
  }
  std::string arm = "[", names, colours;
  for (std::size_t i = 0; i < c.arm_W.size(); ++i) arm += (i ? "," : "") + point(c.arm_W[i]);
  for (std::size_t k = 0; k < c.status_names.size(); ++k) {
    names += (k ? "," : "") + jsonString(c.status_names[k]);
    colours += (k ? "," : "") + jsonString(hex(categorical(static_cast<int>(k))));
  }
  return "{\"name\":" + jsonString(c.name) + ",\"unit\":" + jsonString(c.value_unit) +
         ",\"quantity\":" + jsonString(c.value_quantity) + ",\"value\":\"" + base64(val) + "\"" +
         ",\"hi\":" + jsonString(hi > 0 ? formatFixed(hi, 4) : "0") +
         ",\"size\":" + formatFixed(c.point_size_m, 4) + ",\"status_names\":[" + names +
         "],\"status_colours\":[" + colours + "]" + ",\"pos\":\"" + base64(pos) +
         "\",\"status\":\"" + base64(st) + "\",\"level\":\"" + base64(lv) + "\",\"arm\":" + arm +
         "],\"arm_caption\":" + jsonString(c.arm_caption) + "}";
}

// The scene as JSON for the page's script.
std::string sceneJson(const View3d& v) {
  // Per quantity and unit: the maps of one measure share a colour scale.
  const auto scaleOf = [](const ViewCloud& c) { return c.value_quantity + "\n" + c.value_unit; };
  std::map<std::string, double> hi;
  long total = 0;
  for (const ViewCloud& c : v.clouds) {
    double& h = hi[scaleOf(c)];
    for (std::size_t i = 0; i < c.p_W.size(); ++i) {
      if (drawn(c, i)) ++total;
      if (!std::isnan(c.value[i])) h = std::max(h, c.value[i]);
    }
  }
  const long stride = std::max(1L, (total + kViewMaxPoints - 1) / kViewMaxPoints);
  long shown = 0;
  std::string clouds;
  for (const ViewCloud& c : v.clouds)
    clouds += (clouds.empty() ? "" : ",\n") + cloudJson(c, hi.at(scaleOf(c)), stride, shown);
  std::string solids;
  for (const ViewSolid& s : v.solids) {
    std::string pts;
    for (int k = 0; k < s.points; ++k) pts += (k ? "," : "") + point(s.p_W[k]);
    solids += std::string(solids.empty() ? "" : ",") + "{\"name\":" + jsonString(s.name) +
              ",\"points\":[" + pts + "],\"radius\":" + formatFixed(s.radius_m, 4) + "}";
  }
  std::string viridis_rgb;
  for (int l = 0; l < 255; ++l) {
    const Rgb c = viridis(l / 254.0);
    viridis_rgb += {static_cast<char>(c.r), static_cast<char>(c.g), static_cast<char>(c.b)};
  }
  return "{\"title\":" + jsonString(v.title) + ",\"value_label\":" + jsonString(v.value_label) +
         ",\"stride\":" + std::to_string(stride) + ",\"viridis\":\"" + base64(viridis_rgb) +
         "\",\"solids\":[" + solids + "],\n\"clouds\":[" + clouds + "]}";
}

const char* kStyle = R"(
body { font-family: sans-serif; margin: 0; color: #222; }
header { padding: 6px 12px; }
header h1 { font-size: 18px; margin: 4px 0; }
header p { margin: 4px 0; font-size: 14px; }
#stage { position: relative; }
canvas#view { display: block; width: 100%; height: 70vh; background: #fff; border-top: 1px solid #ccc; border-bottom: 1px solid #ccc; touch-action: none; }
#readout { position: absolute; left: 8px; top: 6px; font-size: 13px; background: rgba(255,255,255,0.85); padding: 2px 6px; pointer-events: none; }
#scale { position: absolute; left: 8px; bottom: 8px; font-size: 13px; background: rgba(255,255,255,0.85); padding: 2px 6px; pointer-events: none; }
#scale .rule { display: block; height: 6px; border: 2px solid #222; border-top: none; margin-top: 2px; }
#legend { padding: 6px 12px; font-size: 14px; display: flex; flex-wrap: wrap; gap: 4px 16px; align-items: center; }
#legend .sw { display: inline-block; width: 12px; height: 12px; margin-right: 4px; vertical-align: middle; }
#legend .bar { display: inline-block; width: 180px; height: 12px; vertical-align: middle; margin: 0 6px; }
#info { padding: 0 12px; font-size: 13px; color: #555; }
select { max-width: 100%; }
)";

// The page's script: three.js scene, the map chosen in the list, colours, the world's axes and
// ground, the scale bar, the read-out under the pointer, the test hook.
const char* kApp = R"JS(
(function () {
  const D = JSON.parse(document.getElementById('armstudy-view-data').textContent);
  const bytes = b64 => { const s = atob(b64), a = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) a[i] = s.charCodeAt(i); return a; };
  const canvas = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  renderer.setClearColor(0xffffff, 1);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, 1, 2);
  camera.add(sun);
  scene.add(camera);
  const controls = new THREE.OrbitControls(camera, canvas);
  const scaleBox = document.getElementById('scale'), readout = document.getElementById('readout');
  let scaleShown = {metres: 0, px: 0};
  // The scale bar: the round length (1-2-5 steps) that spans 60-150 px at the orbit target's depth.
  function updateScale() {
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
    const a = controls.target.clone().project(camera);
    const b = controls.target.clone().add(right).project(camera);
    const pxPerMetre = Math.abs(b.x - a.x) * canvas.clientWidth / 2;
    let len = 10;
    for (const l of [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10])
      if (l * pxPerMetre >= 60) { len = l; break; }
    scaleShown = {metres: len, px: len * pxPerMetre};
    scaleBox.firstChild.textContent = len >= 1 ? len + ' m' : Math.round(len * 1000) + ' mm';
    scaleBox.lastChild.style.width = Math.round(len * pxPerMetre) + 'px';
  }
  const render = () => { camera.updateMatrixWorld(); updateScale(); renderer.render(scene, camera); };
  controls.addEventListener('change', render);
  const viridis = bytes(D.viridis);
  const clouds = D.clouds.map(c => ({name: c.name, unit: c.unit, quantity: c.quantity, hi: c.hi, size: c.size, arm: c.arm, caption: c.arm_caption,
    names: c.status_names, status_colours_css: c.status_colours, colours: c.status_colours.map(h => new THREE.Color(h)),
    pos: new Int32Array(bytes(c.pos).buffer), status: bytes(c.status), level: bytes(c.level),
    value: new Float32Array(bytes(c.value).buffer)}));
  const v3 = p => new THREE.Vector3(p[0], p[1], p[2]);
  const pointOf = (c, k) => new THREE.Vector3(c.pos[3 * k] * 1e-4, c.pos[3 * k + 1] * 1e-4, c.pos[3 * k + 2] * 1e-4);
  const up = new THREE.Vector3(0, 1, 0);
  // A cylinder from a to b (three.js cylinders stand along +y).
  function rod(a, b, r, material) {
    const d = new THREE.Vector3().subVectors(b, a), len = d.length();
    const m = new THREE.Mesh(new THREE.CylinderGeometry(r, r, Math.max(len, 1e-6), 16), material);
    m.position.copy(a).addScaledVector(d, 0.5);
    if (len > 0) m.quaternion.setFromUnitVectors(up, d.normalize());
    return m;
  }
  function ball(c, r, material) {
    const m = new THREE.Mesh(new THREE.SphereGeometry(r, 20, 14), material);
    m.position.copy(c);
    return m;
  }
  // A text label that always faces the camera, `h` metres tall.
  function label(text, at, h, css) {
    const cv = document.createElement('canvas');
    cv.width = 64; cv.height = 64;
    const x = cv.getContext('2d');
    x.fillStyle = css; x.font = 'bold 48px sans-serif'; x.textAlign = 'center'; x.textBaseline = 'middle';
    x.fillText(text, 32, 34);
    const s = new THREE.Sprite(new THREE.SpriteMaterial({map: new THREE.CanvasTexture(cv), depthTest: false}));
    s.position.copy(at);
    s.scale.set(h, h, 1);
    return s;
  }
  const obstacles = new THREE.Group();
  const grey = new THREE.MeshLambertMaterial({color: 0x8d6e4a, transparent: true, opacity: 0.75, side: THREE.DoubleSide});
  for (const s of D.solids) {
    const p = s.points.map(v3), r = Math.max(s.radius, 0.002);
    if (p.length === 1) obstacles.add(ball(p[0], r, grey));
    if (p.length === 2) { obstacles.add(rod(p[0], p[1], r, grey)); obstacles.add(ball(p[0], r, grey)); obstacles.add(ball(p[1], r, grey)); }
    if (p.length === 3) {
      const g = new THREE.BufferGeometry().setFromPoints(p);
      g.computeVertexNormals();
      obstacles.add(new THREE.Mesh(g, grey));
    }
  }
  scene.add(obstacles);
  // Everything the first camera must show: every map's points, every arm with its column, the
  // obstacles.
  const box = new THREE.Box3();
  for (const c of clouds) {
    for (let k = 0; k < c.status.length; ++k) box.expandByPoint(pointOf(c, k));
    for (const p of c.arm) box.expandByPoint(v3(p));
    if (c.arm.length) box.expandByPoint(new THREE.Vector3(c.arm[0][0], c.arm[0][1], Math.min(c.arm[0][2], 0)));
  }
  box.expandByObject(obstacles);
  if (box.isEmpty()) box.expandByPoint(new THREE.Vector3(0, 0, 0));
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.1);
  // The world: its axes at the origin (x red, y green, z blue, labelled) and the ground z = 0 as a
  // grid of 0.1 m squares (0.5 m beyond 4 m).
  const world = new THREE.Group();
  const axisLength = [0.1, 0.2, 0.5, 1, 2].find(l => l >= 0.25 * radius) || 2;
  world.add(new THREE.AxesHelper(axisLength));
  [['x', [1, 0, 0], '#d62728'], ['y', [0, 1, 0], '#2ca02c'], ['z', [0, 0, 1], '#1f4fd6']].forEach(([t, d, css]) =>
    world.add(label(t, v3(d).multiplyScalar(axisLength * 1.12), 0.12 * axisLength, css)));
  const span = Math.max(box.max.x - box.min.x, box.max.y - box.min.y, 0.5) * 1.3;
  const groundStep = span > 4 ? 0.5 : 0.1, cells = 2 * Math.ceil(span / groundStep / 2);
  const ground = new THREE.GridHelper(cells * groundStep, cells, 0xb8b8b8, 0xe2e2e2);
  ground.rotation.x = Math.PI / 2;  // three.js grids lie in x-z; the world's ground is x-y
  const centre0 = box.getCenter(new THREE.Vector3());
  ground.position.set(Math.round(centre0.x / groundStep) * groundStep, Math.round(centre0.y / groundStep) * groundStep, 0);
  world.add(ground);
  scene.add(world);
  const armMaterial = new THREE.MeshLambertMaterial({color: 0x505a6e});
  const jointMaterial = new THREE.MeshLambertMaterial({color: 0xd04a02});
  const columnMaterial = new THREE.MeshLambertMaterial({color: 0x9a9a9a});
  let current = null, points = null, drawnIndex = [], shownMap = 0, mode = 'status', hasColumn = false;
  const legend = document.getElementById('legend'), info = document.getElementById('info');
  const pointsBox = document.getElementById('points');
  function colourOf(c, k) {
    if (mode === 'status') return c.colours[c.status[k]];
    const l = c.level[k];
    if (l === 255) return null;
    return new THREE.Color(viridis[3 * l] / 255, viridis[3 * l + 1] / 255, viridis[3 * l + 2] / 255);
  }
  function show(i) {
    if (current) { scene.remove(current); current.traverse(o => { if (o.geometry) o.geometry.dispose(); }); }
    const c = clouds[i];
    shownMap = i;
    current = new THREE.Group();
    const pos = [], col = [], counts = {};
    drawnIndex = [];
    let zMin = Infinity, zMax = -Infinity;
    for (let k = 0; k < c.status.length; ++k) {
      const rgb = colourOf(c, k);
      if (!rgb) continue;
      const s = c.status[k];
      counts[s] = (counts[s] || 0) + 1;
      const p = pointOf(c, k);
      pos.push(p.x, p.y, p.z);
      col.push(rgb.r, rgb.g, rgb.b);
      drawnIndex.push(k);
      zMin = Math.min(zMin, p.z); zMax = Math.max(zMax, p.z);
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    // A map of several layers is drawn see-through, so that the arm inside it stays visible.
    const layered = zMax - zMin > 1.5 * c.size;
    points = new THREE.Points(g, new THREE.PointsMaterial({size: c.size, vertexColors: THREE.VertexColors,
      transparent: layered, opacity: layered ? 0.35 : 1, depthWrite: !layered}));
    points.visible = pointsBox.checked;
    current.add(points);
    const arm = c.arm.map(v3), r = 0.025;
    for (let k = 0; k + 1 < arm.length; ++k) current.add(rod(arm[k], arm[k + 1], r, armMaterial));
    for (const p of arm) current.add(ball(p, 1.3 * r, jointMaterial));
    // The base's mount: a column from the ground up to a base that stands above it.
    hasColumn = arm.length > 0 && arm[0].z > 0.02;
    if (hasColumn) current.add(rod(new THREE.Vector3(arm[0].x, arm[0].y, 0), arm[0], 1.6 * r, columnMaterial));
    scene.add(current);
    legend.textContent = '';
    if (mode === 'status') {
      for (const s of Object.keys(counts).map(Number).sort((a, b) => a - b)) {
        const e = document.createElement('span');
        e.innerHTML = '<span class="sw"></span>';
        e.firstChild.style.background = c.status_colours_css[s];
        e.appendChild(document.createTextNode(c.names[s] + ' (' + counts[s] + ')'));
        legend.appendChild(e);
      }
    } else {
      const stops = [];
      for (let l = 0; l <= 254; l += 127) stops.push('rgb(' + viridis[3 * l] + ',' + viridis[3 * l + 1] + ',' + viridis[3 * l + 2] + ')');
      const e = document.createElement('span');
      e.appendChild(document.createTextNode((c.quantity || D.value_label) + ' [' + c.unit + ']: 0'));
      const bar = document.createElement('span');
      bar.className = 'bar';
      bar.style.background = 'linear-gradient(to right,' + stops.join(',') + ')';
      e.appendChild(bar);
      e.appendChild(document.createTextNode(c.hi + ' (one scale for the maps of this page that show this quantity)'));
      legend.appendChild(e);
    }
    const arms = document.createElement('span');
    arms.textContent = c.caption + (hasColumn ? '; grey: the column from the ground (z = 0) to the base' : '');
    legend.appendChild(arms);
    info.textContent = pos.length / 3 + ' points shown' + (D.stride > 1 ? ' (every ' + D.stride + 'th point of each map)' : '') +
      '. Axes at the world origin: x red, y green, z blue, ' + (axisLength >= 1 ? axisLength + ' m' : Math.round(axisLength * 1000) + ' mm') +
      ' long; ground grid (z = 0): ' + Math.round(groundStep * 1000) + ' mm squares.';
    render();
  }
  // The read-out of map point k: position [mm], status, the value with its unit.
  function describe(k) {
    const c = clouds[shownMap], p = pointOf(c, k), v = c.value[k];
    const mm = x => Math.round(x * 1000);
    return 'x ' + mm(p.x) + ', y ' + mm(p.y) + ', z ' + mm(p.z) + ' mm: ' + c.names[c.status[k]] + '; ' +
      (isNaN(v) ? 'no ' + (c.quantity || D.value_label) : (c.quantity || D.value_label) + ' ' + v.toPrecision(3) + ' ' + c.unit);
  }
  const ray = new THREE.Raycaster();
  // The map point under canvas pixel (x, y), nearest the camera; -1 for none.
  function pickAt(x, y) {
    if (!points || !points.visible) return -1;
    const ndc = new THREE.Vector2(2 * x / canvas.clientWidth - 1, 1 - 2 * y / canvas.clientHeight);
    ray.params.Points.threshold = 0.6 * clouds[shownMap].size;
    ray.setFromCamera(ndc, camera);
    const hits = ray.intersectObject(points);
    return hits.length ? drawnIndex[hits[0].index] : -1;
  }
  canvas.addEventListener('pointermove', e => {
    const r = canvas.getBoundingClientRect(), k = pickAt(e.clientX - r.left, e.clientY - r.top);
    readout.textContent = k < 0 ? 'point at a map point to read it' : describe(k);
  });
  function fit() {
    const centre = box.getCenter(new THREE.Vector3());
    controls.target.copy(centre);
    // The bounding sphere of everything fits the narrower of the two fields of view.
    const vfov = camera.fov * Math.PI / 180, aspect = canvas.clientWidth / Math.max(canvas.clientHeight, 1);
    const hfov = 2 * Math.atan(Math.tan(vfov / 2) * aspect);
    const distance = 1.05 * radius / Math.sin(Math.min(vfov, hfov) / 2);
    camera.position.copy(centre).add(new THREE.Vector3(1.0, -1.6, 0.9).normalize().multiplyScalar(distance));
    camera.near = radius / 100;
    camera.far = radius * 100;
    camera.lookAt(centre);
    controls.update();
  }
  // Whether the box of everything lies inside the view (all eight corners on the canvas).
  function framed() {
    camera.updateMatrixWorld();
    let outside = 0;
    for (let c = 0; c < 8; ++c) {
      const p = new THREE.Vector3(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z).project(camera);
      if (Math.abs(p.x) > 1 || Math.abs(p.y) > 1) ++outside;
    }
    return outside === 0;
  }
  function resize() {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
    render();
  }
  const list = document.getElementById('map'), modes = document.getElementById('mode');
  D.clouds.forEach((c, i) => { const o = document.createElement('option'); o.value = i; o.textContent = c.name; list.appendChild(o); });
  list.addEventListener('change', () => show(Number(list.value)));
  modes.addEventListener('change', () => { mode = modes.value; show(Number(list.value)); });
  pointsBox.addEventListener('change', () => { if (points) points.visible = pointsBox.checked; render(); });
  window.addEventListener('resize', resize);
  fit();
  resize();
  show(0);
  // For scripts and tests: turn the view about the vertical axis through the target; read a
  // point back through the pointer's path (its screen position, then the pick).
  window.armstudyView = {
    rotate(rad) {
      const off = camera.position.clone().sub(controls.target);
      off.applyAxisAngle(new THREE.Vector3(0, 0, 1), rad);
      camera.position.copy(controls.target).add(off);
      camera.lookAt(controls.target);
      controls.update();
      render();
    },
    show(i, m) { if (m) { mode = m; modes.value = m; } list.value = i; show(i); },
    readoutOf(k) {
      camera.updateMatrixWorld();
      const p = pointOf(clouds[shownMap], k).project(camera);
      const x = (p.x + 1) * canvas.clientWidth / 2, y = (1 - p.y) * canvas.clientHeight / 2;
      const got = pickAt(x, y);
      return {picked: got < 0 ? '' : describe(got), own: describe(k), unit: clouds[shownMap].unit};
    },
    valued() { const c = clouds[shownMap]; for (let k = 0; k < c.value.length; ++k) if (!isNaN(c.value[k])) return k; return -1; },
    parts() { return {axes: axisLength, ground_step: groundStep, column: hasColumn, scale: scaleShown, framed: framed()}; },
    render: render,
    maps: clouds.length
  };
})();
)JS";

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::string threeJsSource(std::string& why) {
  why.clear();
  std::string all;
  for (const char* path : {ARMSTUDY_THREE_JS, ARMSTUDY_THREE_ORBIT_CONTROLS}) {
    std::error_code ec;
    if (std::string(path).empty() || !std::filesystem::is_regular_file(path, ec)) {
      why = std::string("three.js not found (") + (*path ? path : "not found at configure time") +
            "; Debian: apt-get install libjs-three)";
      return "";
    }
    const std::string js = readText(path);
    if (js.find("</script") != std::string::npos) {
      why = std::string(path) + " cannot be inlined (it holds </script)";
      return "";
    }
    all += "<script>\n" + js + "\n</script>\n";
  }
  return all;
}

std::vector<ViewSolid> viewSolids(const std::vector<collision::Obstacle>& obstacles) {
  std::vector<ViewSolid> out;
  for (const collision::Obstacle& o : obstacles) {
    ViewSolid s{o.name, static_cast<int>(o.type), {}, o.radius_m};
    for (int k = 0; k < s.points; ++k) s.p_W[k] = {o.p_W[k].x(), o.p_W[k].y(), o.p_W[k].z()};
    out.push_back(s);
  }
  return out;
}

std::string viewHtml(const View3d& view, const std::string& three_js) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<title>" << htmlEscape(view.title) << "</title>\n<style>" << kStyle << "</style>\n"
    << "</head>\n<body>\n<header>\n<h1>" << htmlEscape(view.title) << "</h1>\n"
    << "<p>Drag to rotate, wheel to zoom, right-drag to pan; point at a map point to read its "
       "position, status and value. "
    << htmlEscape(view.about.empty()
                      ? "The points are the map's grid points in the world frame; the arm (joint "
                        "frame origins, base to tool) stands at the map's reachable pose of the "
                        "largest manipulability; obstacles brown."
                      : view.about)
    << " Details: <a href=\"report.html\">report.html</a>.</p>\n"
    << "<p><label>map <select id=\"map\"></select></label> <label>colour <select "
       "id=\"mode\"><option value=\"status\">status</option><option value=\"value\">"
    << htmlEscape(view.value_label.empty() ? "value" : view.value_label)
    << "</option></select></label> <label><input type=\"checkbox\" "
       "id=\"points\" checked> points</label></p>\n</header>\n"
    << "<div id=\"stage\"><canvas id=\"view\"></canvas><div id=\"readout\">point at a map point "
       "to read it</div><div id=\"scale\"><span></span><span class=\"rule\"></span></div></div>\n"
    << "<div id=\"legend\"></div>\n<p id=\"info\"></p>\n"
    << three_js << "<script type=\"application/json\" id=\"armstudy-view-data\">" << sceneJson(view)
    << "</script>\n<script>" << kApp << "</script>\n</body>\n</html>\n";
  return h.str();
}

}  // namespace armstudy::report
