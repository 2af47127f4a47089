#pragma once
// The ParaView scene of a study (docs/paraview.md): the robot at a configuration and the
// environment obstacles as VTK poly data in the world frame W [m], a .pvd time series of a motion,
// and the pvpython script <output>/<study>/scene.py that opens every spatial file of a run with
// its colouring. Geometry only; io/vtk_io writes the files.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "collision/collision.hpp"
#include "io/vtk_io.hpp"
#include "model/model.hpp"
#include "study/writer.hpp"

namespace armstudy::scene {

// The arm at q: part 0 = skeleton polyline (base origin, every joint frame origin, TCP), part 1 =
// the surfaces of its collision volumes (spheres, capsules, swept triangles; none when the design
// has no collision model). Point arrays "part" and "body" (-1 = base, i = link after joint i);
// field data with units and legend.
io::PolyDataSet robotPolyData(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q);

// The arm's skeleton at q: the base origin, every joint frame origin and the TCP, in W [m] (part 0
// of robotPolyData).
std::vector<Eigen::Vector3d> skeletonPoints(const Model& model,
                                            const Eigen::Ref<const Eigen::VectorXd>& q);

// The obstacles' surfaces; point array "obstacle" (index into `obstacles`, legend names them).
io::PolyDataSet obstaclePolyData(const std::vector<collision::Obstacle>& obstacles);

// One step of a robot motion for writeMotion.
struct MotionStep {
  double t = 0;  // s
  Eigen::VectorXd q;
};

// Writes the robot at each step as <rel_stem>/step_<k>.vtp and the collection <rel_stem>.pvd
// (relative to the output folder) through `out`; returns the .pvd path relative to it.
std::string writeMotion(Writer& out, const std::string& rel_stem, const Model& model,
                        const std::vector<MotionStep>& steps);

// At most `max_steps` sample indices spread evenly over [0, n) with the first and the last.
std::vector<int> evenSamples(int n, int max_steps);

// The pvpython script that opens `files` (paths relative to the script's folder; spatial ones:
// .vti, .vts, .vtp, .pvd) in one view: maps coloured by manipulability (else status, ...), robot
// and obstacles grey, boundary surfaces translucent; files whose field data says their
// coordinates are not world metres are loaded hidden. `pvpython scene.py --screenshot out.png`
// renders offscreen into a PNG.
std::string sceneScript(const std::string& study_name, const std::vector<std::string>& files);

// True for the file types sceneScript opens.
bool isSpatialFile(const std::string& rel);

}  // namespace armstudy::scene
