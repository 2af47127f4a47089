// The pvpython scene script of a study (study/scene.hpp, docs/paraview.md).
#include <string>
#include <vector>

#include "io/vtk_io.hpp"
#include "study/scene.hpp"

namespace armstudy::scene {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// What the script does with the listed files; FILES and WORLD are filled in before it.
constexpr const char* kScriptBody = R"PY(
# Colour by the first point array whose name starts with one of these (maps: manipulability,
# else the status enum, ...); robot, obstacles and motions are grey, boundary surfaces translucent.
COLOUR_BY = ("manipulability_optimised_normalised", "manipulability", "status", "max_current_ratio",
             "reached_by_count", "mean_residual_max_abs", "residual", "in_contact", "time")
GREY = (0.62, 0.62, 0.62)
OBSTACLE_GREY = (0.40, 0.40, 0.40)

import os
import re
import sys
from paraview import servermanager
from paraview.simple import *

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


def main():
    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 1
    bars = set()
    for rel in FILES:
        source = OpenDataFile(os.path.join(HERE, rel))
        RenameSource(rel, source)
        source.UpdatePipeline()
        shown = Show(source, view)
        if field_strings(source, "coordinates")[:1] != [WORLD]:
            Hide(source, view)  # e.g. a map over (gamma, z): not in metres, kept for inspection
            continue
        name = os.path.basename(rel)
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
        if rel.endswith(".vti") and all(extent[2 * a + 1] > extent[2 * a] for a in range(3)):
            shown.SetRepresentationType("Points")  # a 3-D grid: every point visible
        shown.PointSize = 4.0
        shown.LineWidth = 2.0
        array = colour_array(source)
        if array is None:
            continue
        ColorBy(shown, ("POINTS", array))
        shown.RescaleTransferFunctionToDataRange(False, True)
        if not bars:  # one colour bar (the first map's), titled with its unit
            bars.add(array)
            shown.SetScalarBarVisibility(view, True)
            bar = GetScalarBar(GetColorTransferFunction(array), view)
            base = re.sub(r"_o[0-9]+$", "", array)  # reach arrays per orientation: manipulability_o1
            units = [u.split(": ", 1)[1].split(" (")[0] for u in field_strings(source, "units")
                     if u.startswith(base + ": ")]
            bar.Title = array + (" [" + units[0] + "]" if units else "")
            bar.ComponentTitle = ""
            bar.Orientation = "Horizontal"  # a long title fits below the scene
            bar.WindowLocation = "Lower Center"
            bar.ScalarBarLength = 0.5
    view.CameraViewUp = [0, 0, 1]
    view.ResetActiveCameraToNegativeY()
    camera = GetActiveCamera()
    camera.Elevation(25)
    camera.Azimuth(-35)
    view.ResetCamera()
    Render(view)
    if "--screenshot" in sys.argv:
        SaveScreenshot(sys.argv[sys.argv.index("--screenshot") + 1], view, ImageResolution=[1280, 800])
    elif sys.argv and sys.argv[0].endswith("scene.py"):
        Interact(view)  # pvpython scene.py: an interactive window


main()
)PY";

}  // namespace

bool isSpatialFile(const std::string& rel) {
  return endsWith(rel, ".vti") || endsWith(rel, ".vts") || endsWith(rel, ".vtp") || endsWith(rel, ".pvd");
}

std::string sceneScript(const std::string& study_name, const std::vector<std::string>& files) {
  std::string s = "# ParaView scene of the armstudy study \"" + study_name +
                  "\" (docs/paraview.md), written by `armstudy run`.\n"
                  "#   pvpython scene.py                         an interactive window\n"
                  "#   pvpython scene.py --screenshot scene.png  renders offscreen into a PNG\n"
                  "#   paraview --script=scene.py                in the ParaView GUI\n"
                  "WORLD = \"" + std::string(io::kWorldMetres) + "\"\nFILES = [\n";
  for (const std::string& f : files)
    if (isSpatialFile(f) && f.find("/step_") == std::string::npos) s += "    \"" + f + "\",\n";
  s += "]\n";
  return s + kScriptBody;
}

}  // namespace armstudy::scene
