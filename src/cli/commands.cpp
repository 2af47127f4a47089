// The command table: every armstudy command with its --help text.
#include "cli/commands.hpp"

namespace armstudy::cli {

namespace {

// clang-format off
const Command kCommands[] = {
    {"describe", addDescribeCommand,
     "Print a design's kinematic table (thesis Table 3.1 layout), DoF, joint limits and the\n"
     "assumptions its author recorded. Validates the file on the way."},
    {"fk", addFkCommand,
     "Forward kinematics: pose of every joint frame and the TCP for a joint vector.\n"
     "Positions in metres, orientation as Cardan angles alpha, beta, gamma (R = Rx Ry Rz).\n"
     "Example: armstudy fk designs/first_prototype_6dof.toml --q 0.3,0,0,0,0,0\n"
     "         armstudy fk ur5_robot.urdf --base base_link --tip tool0 --q 0,-1.57,0,0,0,0 --json"},
    {"draw", addDrawCommand,
     "Draw a design's arm at q = 0 (clamped into the limits) or at --q as an SVG: side (x-z) and\n"
     "top (x-y) view of the links, every body frame (x red, y green, z blue) and joint axis (dashed).\n"
     "Example: armstudy draw ur5_robot.urdf --tip tool0 --deg --q 0,-90,90,0,90,0 --out ur5.svg"},
    {"run", addRunCommand,
     "Load, validate and run a study. Results go to <output>/<study name>/ with a manifest\n"
     "(version, git revision, input hashes, settings, timings). Nothing is written when the\n"
     "study or any design it names is invalid.\n"
     "Example: armstudy run studies/spraying_row.toml --threads 2"},
    {"baseline", addBaselineCommand,
     "Run a study and record its summary metrics as the study's baseline (a small JSON file\n"
     "beside the study, default <study>.baseline.json, or [regression].baseline). Commit it.\n"
     "Example: armstudy baseline studies/regression.toml"},
    {"check", addCheckCommand,
     "Re-run a study and compare its summary metrics with the recorded baseline, using the\n"
     "tolerances of the study's [[regression.tolerance]] rules. Prints what moved (metric,\n"
     "baseline, now, tolerance, verdict). Exit status 0 when everything is within tolerance,\n"
     "3 when something moved beyond it, 2 for bad input (e.g. a baseline of another study).\n"
     "Example: armstudy check studies/regression.toml --json output/regression/check.json"},
    {"compare", addCompareCommand,
     "Compare a design's model with measurements: RMSE, bias and max per channel, plots of measured\n"
     "vs predicted and residual vs every operating variable, residual bins the noise cannot explain\n"
     "flagged (drive: speed x load map; tcp/trajectory: joint-variable bins and workspace cells, also\n"
     "as VTK .vti/.vtp); appends to history.csv.\n"
     "Examples: armstudy compare designs/final_prototype_9dof.toml --drive j6 --data studies/data/drive_testbed_module_b2.csv\n"
     "          armstudy compare designs/final_prototype_7dof.toml --kind tcp --data tcp.csv"},
    {"fit", addFitCommand,
     "Rank the candidate effects that could be missing from a design's model by k-fold cross-validated\n"
     "error (with held-out-by-region scores, confidence intervals and identifiability warnings),\n"
     "optionally add effects, and write a calibrated copy of the design (the effects of each kind\n"
     "are listed below the options).\n"
     "Examples: armstudy fit designs/final_prototype_9dof.toml --drive j6 --data studies/data/drive_testbed_module_b2.csv --auto\n"
     "          armstudy fit designs/final_prototype_7dof.toml --kind trajectory --data run.csv --add payload"},
    {"synth", addSynthCommand,
     "Virtual test bed / robot: write measurement CSV data from a design plus hidden effects and noise\n"
     "(seeded, reproducible).\n"
     "  drive: test-bed sweep of one drive; speeds in both directions, loads oppose the motion, the\n"
     "         housing temperature warms up over the run (--drive, --speeds, --loads, --temperature)\n"
     "  tcp: joint positions uniform in the central part of the limits, measured TCP = forward\n"
     "       kinematics with the hidden effects + noise (--rows, --noise [m], --orientation)\n"
     "  trajectory: smooth random sum-of-sines joint motion, efforts by inverse dynamics + drive chain\n"
     "       with the hidden effects + noise (--duration, --rate, --noise [N m, N or A], --currents, --no-qdd)\n"
     "Examples: armstudy synth designs/final_prototype_9dof.toml --drive j6 --hide stribeck:stribeck_velocity=60 --out bed.csv\n"
     "          armstudy synth designs/final_prototype_7dof.toml --kind tcp --hide joint_offset.j3:offset=0.01 --out tcp.csv\n"
     "          armstudy synth designs/final_prototype_7dof.toml --kind trajectory --hide payload --out run.csv"},
    {"dynamics", addDynamicsCommand,
     "Inverse dynamics (thesis eq. 3.22-3.28): joint torques/forces Q for a state (q, qd, qdd),\n"
     "the static holding part g(q) and optionally the mass matrix M(q). Q in N m (revolute) or N\n"
     "(prismatic). Needs [[inertia]] data in the design (docs/dynamics.md).\n"
     "Example: armstudy dynamics designs/final_prototype_9dof.toml --q 0,0,30,0,0,0,0,0,0 --deg"},
    {"approach", addApproachCommand,
     "Plan a radial approach to a fruit around its stem (thesis section 5.3.2) and print the\n"
     "task-space trajectory w = (x, y, z, alpha, beta, gamma) with its first and second time\n"
     "derivatives as CSV (SI units, radians). Coordinates in the task frame W.\n"
     "Example (thesis Fig. 5.8): armstudy approach --start 0.55,0.79,1.0 --stem 0.43,0.8\n"
     "  --fruit 0.43,0.762,0.9 --duration 2 --entry-radius 0.1 --s-a 0.1 --s-e 0.8"},
    {"fit-ssv", addFitSsvCommand,
     "Fit swept-sphere collision volumes to a link mesh and write them into the design.\n"
     "The mesh (closed STL or OFF surface) must be given in the link's frame; every mesh vertex\n"
     "ends up inside the fitted volumes. The link's existing [[collision]] tables are replaced.\n"
     "Example: armstudy fit-ssv designs/final_prototype_9dof.toml --link j3 --mesh upper_arm.stl\n"
     "         --scale 0.001 --out my_design.toml"},
    {"convert", addConvertCommand,
     "Convert a design between URDF and the design TOML format, by the extensions of IN and OUT:\n"
     ".urdf -> .toml (the chain --base .. --tip, with inertias, limits and collision volumes "
     "fitted\n"
     "to the links' collision geometry) or .toml -> .urdf (kinematics, inertias, limits; "
     "docs/design-format.md).\n"
     "Joint values keep their meaning both ways.\n"
     "Example: armstudy convert ur5_robot.urdf ur5.toml --base base_link --tip tool0\n"
     "         armstudy convert designs/final_prototype_7dof.toml final_7dof.urdf"},
};
// clang-format on

}  // namespace

std::span<const Command> commands() { return kCommands; }

}  // namespace armstudy::cli
