// The pvpython scene script of a study (study/scene.hpp, docs/paraview.md).
#include <cstdio>
#include <string>
#include <vector>

#include "io/vtk_io.hpp"
#include "study/scene.hpp"

namespace armstudy::scene {

namespace {

// The code point `cp` of the UTF-8 sequence starting at s[i] and its length (2 to 4: a valid
// sequence, not overlong, no surrogate); else 1 and the byte itself.
std::size_t utf8Next(const std::string& s, std::size_t i, unsigned& cp) {
  const auto c = static_cast<unsigned char>(s[i]);
  cp = c;
  const std::size_t n = c >= 0xc2 && c <= 0xdf   ? 2
                        : c >= 0xe0 && c <= 0xef ? 3
                        : c >= 0xf0 && c <= 0xf4 ? 4
                                                 : 1;
  if (n == 1 || i + n > s.size()) return 1;
  unsigned v = c & (0x7f >> n);
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if ((b & 0xc0) != 0x80) return 1;
    v = (v << 6) | (b & 0x3f);
  }
  const bool overlong = (n == 3 && v < 0x800) || (n == 4 && v < 0x10000);
  if (overlong || (v >= 0xd800 && v <= 0xdfff) || v > 0x10ffff) return 1;
  cp = v;
  return n;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A Python string literal of `s` in ASCII: quotes, backslashes and control characters escaped,
// other characters as \u / \U escapes of their UTF-8 code points, bytes that are not UTF-8 as
// the lone surrogates Python gives undecodable file-name bytes (\udc80-\udcff). Text, never code.
std::string pythonString(const std::string& s) {
  std::string o = "\"";
  char buf[16];
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      o += '\\';
      o += static_cast<char>(c);
      ++i;
      continue;
    }
    if (c >= 0x20 && c < 0x7f) {
      o += static_cast<char>(c);
      ++i;
      continue;
    }
    unsigned cp = 0;
    const std::size_t n = utf8Next(s, i, cp);
    if (n == 1 && c >= 0x80) cp = 0xdc00 | c;  // not UTF-8: as Python's surrogateescape
    std::snprintf(buf, sizeof buf, cp > 0xffff ? "\\U%08x" : cp > 0xff ? "\\u%04x" : "\\x%02x", cp);
    o += buf;
    i += n;
  }
  return o + "\"";
}

// What the script does with the listed files; FILES and WORLD are filled in before it.
constexpr const char* kScriptBody = R"PY(
# Colour by the first point array whose name starts with one of these (maps: manipulability,
# else the status enum, ...); robot, obstacles and motions are grey, boundary surfaces translucent.
# Magnitudes get a sequential scale (viridis), signed quantities a diverging one centred on 0,
# enumerations one colour per value named from the file's legend.
COLOUR_BY = ("manipulability_optimised_normalised", "manipulability", "status", "max_current_ratio",
             "reached_by_count", "mean_over_threshold_max", "residual", "in_contact", "time")
GREY = (0.62, 0.62, 0.62)
OBSTACLE_GREY = (0.40, 0.40, 0.40)
NAN_COLOUR = [0.86, 0.86, 0.86]  # light grey: no value at this point (no solution), as in the SVG maps
SIZE = [1280, 800]  # the view and its screenshots [pixels]; fonts are sized for it
BAR_WIDTH = 0.26    # share of the width on the right kept for the colour bars
FONT = 15           # colour-bar title and label size [points]
MAX_BARS = 3        # colour scales beside the scene; a file needing one more is loaded hidden

import math
import os
import re
import sys
from paraview import servermanager
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkCommonDataModel import vtkStaticPointLocator

HERE = os.path.dirname(os.path.abspath(__file__))


def field_strings(source, name):
    """The string field data `name` of a reader's output (first block of a collection)."""
    data = servermanager.Fetch(source)
    if data is not None and data.IsA("vtkCompositeDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        data = None if it.IsDoneWithTraversal() else it.GetCurrentDataObject()
    array = data.GetFieldData().GetAbstractArray(name) if data is not None else None
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())] if array else []


def colour_array(source):
    names = list(source.PointData.keys())
    for key in COLOUR_BY:
        for n in names:
            if n.startswith(key):
                return n
    return None


def unit_of(source, array):
    """The unit of a point array from the field data `units` ("<array>: <unit> (<note>)")."""
    base = re.sub(r"_o[0-9]+$", "", array)  # reach arrays per orientation: manipulability_o1
    for u in field_strings(source, "units"):
        if u.startswith(base + ": "):
            unit = u.split(": ", 1)[1].split(" (")[0]
            return "-" if unit == "1" else unit
    return None


def categories(source, array):
    """The meanings of an enumeration's values from the field data `legend` ("<array> <v>: <text>")."""
    out = []
    for entry in field_strings(source, "legend"):
        m = re.match(re.escape(array) + r" (-?[0-9]+): (.*)$", entry)
        if m:
            out.append((int(m.group(1)), m.group(2).split(" (")[0]))
    return sorted(out)


PALETTE = [(0.12, 0.47, 0.71), (1.0, 0.50, 0.05), (0.17, 0.63, 0.17), (0.84, 0.15, 0.16),
           (0.58, 0.40, 0.74), (0.55, 0.34, 0.29), (0.89, 0.47, 0.76), (0.50, 0.50, 0.50)]


def wrapped(title, width=26):
    """A long title broken after underscores or spaces into lines of about `width` characters."""
    lines, line = [], ""
    for part in re.findall(r"[^_ ]*[_ ]?", title):
        if line and len(line) + len(part) > width:
            lines.append(line.rstrip())
            line = ""
        line += part
    return "\n".join(lines + [line.rstrip()]) if line else "\n".join(lines)


def style_bar(bar, title, index, categorical):
    bar.Title = wrapped(title)
    bar.ComponentTitle = ""
    bar.Orientation = "Vertical"
    bar.WindowLocation = "Any Location"
    bar.Position = [1.0 - BAR_WIDTH + 0.01, 0.70 - 0.32 * index]
    bar.ScalarBarLength = 0.20
    bar.TitleFontSize = FONT
    bar.LabelFontSize = FONT - 2
    bar.TitleJustification = "Left"
    bar.HorizontalTitle = 1
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = "%-#.3g"
    bar.RangeLabelFormat = "%-#.3g"
    bar.DrawTickMarks = 1
    # All text right of the bar, away from the scene (categories are "annotations" to ParaView).
    bar.TextPosition = ("Ticks left/bottom, annotations right/top" if categorical
                        else "Ticks right/top, annotations left/bottom")


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(v):
    n = math.sqrt(sum(x * x for x in v)) or 1.0
    return [x / n for x in v]


def frame_scene(view, bounds):
    """Camera: the data's bounding box inside the part of the view left of the colour bars."""
    renderer = view.GetRenderer()
    camera = GetActiveCamera()
    corners = [(bounds[i], bounds[2 + j], bounds[4 + k]) for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    right_edge = 1.0 - BAR_WIDTH
    for _ in range(30):
        Render(view)
        xs, ys = [], []
        for c in corners:
            renderer.SetWorldPoint(c[0], c[1], c[2], 1.0)
            renderer.WorldToView()
            x, y, _ = renderer.GetViewPoint()  # -1..1 across the viewport
            xs.append((x + 1) / 2)
            ys.append((y + 1) / 2)
        # Pan: the box's centre to the centre of the free part; then zoom until it fits with a margin.
        dx = (min(xs) + max(xs)) / 2 - right_edge / 2
        dy = (min(ys) + max(ys)) / 2 - 0.5
        scale = max((max(xs) - min(xs)) / (0.92 * right_edge), (max(ys) - min(ys)) / 0.92)
        if abs(dx) < 0.005 and abs(dy) < 0.005 and 0.97 < scale <= 1.0:
            break
        # Move the camera within its view plane by the offset (in units of the view's width at the focal point).
        fp, pos = list(camera.GetFocalPoint()), list(camera.GetPosition())
        dist = camera.GetDistance()
        height = 2 * dist * math.tan(math.radians(camera.GetViewAngle()) / 2)
        width = height * SIZE[0] / SIZE[1]
        d = [fp[i] - pos[i] for i in range(3)]
        right = unit(cross(d, camera.GetViewUp()))
        up = unit(cross(right, d))  # the view-up orthogonal to the direction of view
        shift = [dx * width * right[i] + dy * height * up[i] for i in range(3)]
        camera.SetFocalPoint(*[fp[i] + shift[i] for i in range(3)])
        camera.SetPosition(*[pos[i] + shift[i] for i in range(3)])
        camera.Dolly(1.0 / scale if scale > 0 else 1.0)


def ellipsoid_glyphs(source, rel):
    """Manipulability ellipsoids (the 3 x 3 tensor array `ellipsoid_tensor`: semi-axes in its
    eigenvalues) as ParaView's tensor glyphs, scaled so that the largest semi-axis is 0.45 x the
    smallest distance between two points (none overlaps), coloured by `manipulability`."""
    data = servermanager.Fetch(source)
    # The smallest distance from a point to its nearest other point (a locator, not all pairs).
    locator = vtkStaticPointLocator()
    locator.SetDataSet(data)
    locator.BuildLocator()
    ids = vtkIdList()
    distances = []
    for i in range(data.GetNumberOfPoints()):
        p = data.GetPoint(i)
        locator.FindClosestNPoints(2, p, ids)
        for k in range(ids.GetNumberOfIds()):
            d = math.dist(p, data.GetPoint(ids.GetId(k)))
            if d > 0:
                distances.append(d)
    spacing = min(distances or [0.1])
    largest = max(source.PointData["semi_axes"].GetRange(k)[1] for k in range(3)) or 1.0
    glyphs = TensorGlyph(Input=source, GlyphType="Sphere")
    glyphs.Tensors = ["POINTS", "ellipsoid_tensor"]
    glyphs.ScaleFactor = 0.45 * spacing / largest
    if "manipulability" in source.PointData.keys():
        glyphs.Scalars = ["POINTS", "manipulability"]
        glyphs.ColorGlyphs = 1
        glyphs.Colorby = "input scalars"
    RenameSource(rel + " (ellipsoids)", glyphs)
    glyphs.UpdatePipeline()
    return glyphs


def main():
    bars_on = "--no-bars" not in sys.argv
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = SIZE
    view.OrientationAxesVisibility = 1
    coloured = {}  # quantity (array name without the orientation suffix _oK) -> [range, source, arrays]
    bounds = None
    for rel in FILES:
        source = OpenDataFile(os.path.join(HERE, rel))
        RenameSource(rel, source)
        source.UpdatePipeline()
        if field_strings(source, "coordinates")[:1] != [WORLD]:
            continue  # e.g. a map over (gamma, z): not in metres, in the pipeline browser but not shown
        name = os.path.basename(rel)
        folder = os.path.dirname(rel)
        if ("/calibrated/" in "/" + rel or name == "comparison.vti" or
                (name.startswith("before_") and os.path.exists(os.path.join(HERE, folder, "after_" + name[7:]))) or
                (name.endswith("_ellipsoids_plain.vtp") and
                 os.path.exists(os.path.join(HERE, folder, name.replace("_plain.vtp", "_optimised.vtp"))))):
            # Loaded hidden (one click in the pipeline browser): the model before calibration, the
            # calibrated copy's duplicate of "after", the designs' comparison on the maps' own points,
            # the plain ellipsoids where the optimised ones are drawn at the same points.
            continue
        drawn = source
        if "ellipsoid_tensor" in source.PointData.keys():
            drawn = ellipsoid_glyphs(source, rel)  # the ellipsoids themselves, coloured as their points
        shown = Show(drawn, view)
        b = drawn.GetDataInformation().GetBounds()
        if b[0] <= b[1]:
            bounds = list(b) if bounds is None else [min(bounds[i], b[i]) if i % 2 == 0 else max(bounds[i], b[i])
                                                     for i in range(6)]
        if "robot" in name or "obstacles" in name or rel.endswith(".pvd"):
            shown.ColorArrayName = ["POINTS", ""]  # solid colour
            shown.AmbientColor = shown.DiffuseColor = OBSTACLE_GREY if "obstacles" in name else GREY
            shown.LineWidth = 3.0
            continue
        if "_surface" in name:
            shown.ColorArrayName = ["POINTS", ""]  # solid colour
            shown.Opacity = 0.3
            continue
        extent = source.GetDataInformation().GetExtent()
        if rel.endswith(".vti") and sum(extent[2 * a + 1] > extent[2 * a] for a in range(3)) != 2:
            shown.SetRepresentationType("Points")  # a 3-D grid or a line of points: every point visible
        shown.PointSize = 4.0
        shown.LineWidth = 2.0
        array = colour_array(drawn)
        if array is None:
            continue
        quantity = re.sub(r"_o[0-9]+$", "", array)  # reach maps: manipulability_o1 per orientation
        if quantity not in coloured and len(coloured) == MAX_BARS:
            Hide(drawn, view)  # no room for another colour scale: kept in the pipeline browser
            print("hidden (a colour scale too many): %s by %s" % (rel, array))
            continue
        ColorBy(shown, ("POINTS", array))
        shown.SetScalarBarVisibility(view, False)
        r = drawn.PointData[array].GetRange()
        if quantity not in coloured:
            coloured[quantity] = [r, source, [array]]
        else:  # one colour scale per quantity over all the files and orientations that show it
            entry = coloured[quantity]
            entry[0] = (min(entry[0][0], r[0]), max(entry[0][1], r[1]))
            if array not in entry[2]:
                entry[2].append(array)
    for index, (quantity, (r, source, arrays)) in enumerate(coloured.items()):
        cats = categories(source, arrays[0])
        unit = unit_of(source, arrays[0])
        title = quantity + (" [" + unit + "]" if unit else "")
        for array in arrays:  # ParaView keeps a colour map per array name: give them all the same
            lut = GetColorTransferFunction(array)
            if cats:  # an enumeration: one colour per value, named from the legend
                lut.InterpretValuesAsCategories = 1
                lut.Annotations = sum([[str(v), "%d %s" % (v, text)] for v, text in cats], [])
                lut.IndexedColors = sum([list(PALETTE[k % len(PALETTE)]) for k in range(len(cats))], [])
            elif r[0] < 0 < r[1]:  # signed (residuals): diverging, white at 0, symmetric
                lut.ApplyPreset("Cool to Warm", True)
                lut.RescaleTransferFunction(-max(-r[0], r[1]), max(-r[0], r[1]))
            else:  # magnitudes: a sequential scale (dark = small)
                lut.ApplyPreset("Viridis (matplotlib)", True)
                lut.RescaleTransferFunction(r[0], r[1] if r[1] > r[0] else r[0] + 1.0)
            lut.NanColor = NAN_COLOUR  # where the quantity does not exist (e.g. no solution)
        if bars_on:  # one bar per quantity (the first array's colour map stands for all)
            bar = GetScalarBar(GetColorTransferFunction(arrays[0]), view)
            style_bar(bar, title, index, bool(cats))
            if not cats:  # (ParaView would draw a NaN swatch's text left of the bar, over the scene)
                bar.Title = bar.Title + "\nlight grey: none (NaN)"
            bar.Visibility = 1
        print("coloured by %s, %s..%s%s" % (title, r[0], r[1], " (categories)" if cats else ""))
    view.CameraViewUp = [0, 0, 1]
    view.ResetActiveCameraToNegativeY()
    camera = GetActiveCamera()
    camera.Elevation(25)
    camera.Azimuth(-35)
    view.ResetCamera()
    if bounds is not None:
        frame_scene(view, bounds)
    Render(view)
    if "--screenshot" in sys.argv:
        SaveScreenshot(sys.argv[sys.argv.index("--screenshot") + 1], view, ImageResolution=SIZE)
    elif sys.argv and sys.argv[0].endswith("scene.py"):
        Interact(view)  # pvpython scene.py: an interactive window


main()
)PY";

}  // namespace

bool isSpatialFile(const std::string& rel) {
  return endsWith(rel, ".vti") || endsWith(rel, ".vts") || endsWith(rel, ".vtp") ||
         endsWith(rel, ".pvd");
}

std::string sceneScript(const std::string& study_name, const std::vector<std::string>& files) {
  std::string s = "# ParaView scene of the armstudy study " + pythonString(study_name) +
                  " (docs/paraview.md), written by `armstudy run`.\n"
                  "#   pvpython scene.py                         an interactive window\n"
                  "#   pvpython scene.py --screenshot scene.png  renders offscreen into a PNG "
                  "(--no-bars: without colour bars)\n"
                  "#   paraview --script=scene.py                in the ParaView GUI\n"
                  "WORLD = " +
                  pythonString(io::kWorldMetres) + "\nFILES = [\n";
  for (const std::string& f : files)  // as literals: a name is text, never code
    if (isSpatialFile(f) && f.find("/step_") == std::string::npos)
      s += "    " + pythonString(f) + ",\n";
  s += "]\n";
  return s + kScriptBody;
}

}  // namespace armstudy::scene
