#pragma once
// The study's interactive 3-D view (output/<study>/view.html): one self-contained page that shows
// the reach maps' points in the world frame, coloured by status or manipulability, the arm at its
// best pose as cylinders between its joint frames (on a column down to the ground when its base
// stands above it) and the study's obstacles, with the world axes, the ground grid, a scale bar and
// a read-out of the point under the pointer, rotatable with the mouse. Built on three.js from
// Debian's libjs-three (three.min.js and its OrbitControls), read at run time from the files CMake
// found and inlined, so the page works offline from the one file. The bytes depend only on the
// scene: fixed number formatting, no dates.
#include <array>
#include <string>
#include <vector>

#include "collision/collision.hpp"

namespace armstudy::report {

// One map's points (e.g. a reach grid of one design) and the arm that belongs to it.
struct ViewCloud {
  std::string name;                          // shown in the page's map list
  std::vector<std::array<double, 3>> p_W;    // point positions in W [m]
  std::vector<int> status;                   // per point: category (colour: categorical(status))
  std::vector<std::string> status_names;     // per category; "" = its points are not drawn
  std::vector<double> value;                 // per point: manipulability, NaN where none
  std::string value_unit = "m^3";            // the value's unit
  std::string value_quantity;                // what the value measures (e.g. the task rows of a
                                             // manipulability): maps of one quantity and unit
                                             // share a colour scale, others have their own
  double point_size_m = 0.01;                // drawn size of a point [m] (about the grid step)
  std::vector<std::array<double, 3>> arm_W;  // the arm's joint frame origins, base to TCP [m]
  std::string arm_caption;                   // what the arm's pose is
};

// An obstacle: a sphere (1 point), a capsule (2 points) or a triangle (3 points), with a radius.
struct ViewSolid {
  std::string name;
  int points = 1;
  std::array<std::array<double, 3>, 3> p_W{};  // m
  double radius_m = 0;
};

struct View3d {
  std::string title;
  std::vector<ViewCloud> clouds;
  std::vector<ViewSolid> solids;
  std::string value_label;  // the value's quantity, for the colour bar (each map names its unit)
  // What the points, their values and the arm are, for the page's header; "" = the reach maps'
  // words (grid points, the arm at the reachable pose of the largest manipulability).
  std::string about;
};

// Obstacles as the view draws them, in their order.
std::vector<ViewSolid> viewSolids(const std::vector<collision::Obstacle>& obstacles);

// At most this many points in a page: beyond it every k-th point of each map is kept (in index
// order), so the page stays a few MB whatever the grid.
inline constexpr long kViewMaxPoints = 150000;

// three.js and its OrbitControls as found at configure time (ARMSTUDY_THREE_JS): the scripts'
// text, or "" with `why` set when a file is missing.
std::string threeJsSource(std::string& why);

// The page. `three_js` is threeJsSource()'s text, inlined.
std::string viewHtml(const View3d& view, const std::string& three_js);

}  // namespace armstudy::report
