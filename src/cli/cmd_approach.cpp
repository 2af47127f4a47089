#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli/commands.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "io/units.hpp"
#include "trajectory/approach_planner.hpp"

namespace armstudy::cli {

void checkSampling(double duration_s, double rate_Hz) {
  auto fail = [](const char* option, const std::string& why) {
    throw InputError("command line", 0, option, why);
  };
  if (!(duration_s > 0 && duration_s <= defaults::kMaxDuration_s))
    fail("--duration", "the duration lies in (0, " + formatG(defaults::kMaxDuration_s, 6) + "] s");
  if (!(rate_Hz > 0 && rate_Hz <= defaults::kMaxSampleRate_Hz))
    fail("--rate",
         "the sample rate lies in (0, " + formatG(defaults::kMaxSampleRate_Hz, 6) + "] Hz");
  if (!(duration_s * rate_Hz >= 1))
    fail("--rate", "duration x rate must give at least one step (rate >= 1 / duration)");
  if (duration_s * rate_Hz > defaults::kMaxTrajectorySamples)
    fail("--rate",
         "duration x rate exceeds " + formatG(defaults::kMaxTrajectorySamples, 6) + " samples");
}

namespace {

// Every value of a point option is a plausible length.
void checkLengths(const std::vector<double>& values, const char* option) {
  const Dimension dim = Dimension::Length;
  for (double v : values)
    if (const std::string bad = implausible(v, &dim); !bad.empty())
      throw InputError("command line", 0, option, bad);
}

}  // namespace

void addApproachCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::vector<double> start, stem, fruit, start_cardan, reference;
    ApproachPlannerOptions opt;
    double rate_hz = 100;
    std::string out;
  };
  auto a = std::make_shared<Args>();
  a->opt.duration_s = 0;
  cmd->add_option("--start", a->start, "Start TCP position x,y,z [m]")
      ->delimiter(',')
      ->expected(3)
      ->required();
  cmd->add_option("--stem", a->stem, "Stem position x,y [m]")
      ->delimiter(',')
      ->expected(2)
      ->required();
  cmd->add_option("--fruit", a->fruit, "Fruit centre x,y,z [m]")
      ->delimiter(',')
      ->expected(3)
      ->required();
  cmd->add_option("--start-cardan", a->start_cardan,
                  "Start Cardan angles alpha,beta,gamma [rad], default 0")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--reference", a->reference, "Reference point x,y (robot base) [m], default 0,0")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--duration", a->opt.duration_s, "Duration T [s] (> 0)")->required();
  cmd->add_option("--entry-radius", a->opt.entry_radius_m, "Entry radius r_e [m]")
      ->capture_default_str();
  cmd->add_option("--s-a", a->opt.s_a, "Tuning parameter s_a")->capture_default_str();
  cmd->add_option("--s-e", a->opt.s_e, "Tuning parameter s_e (entry point)")->capture_default_str();
  cmd->add_option("--exp-scale", a->opt.exp_scale_m, "Length scale L of r(s) = L exp(-a s) + b [m]")
      ->capture_default_str();
  cmd->add_option("--rate", a->rate_hz, "Samples per second")->capture_default_str();
  cmd->add_option("--out", a->out, "Write the CSV to this file instead of stdout");
  setAction(cmd, action, [a] {
    checkSampling(a->opt.duration_s, a->rate_hz);
    checkLengths(a->start, "--start");
    checkLengths(a->stem, "--stem");
    checkLengths(a->fruit, "--fruit");
    checkLengths(a->reference, "--reference");
    std::string err;
    if (!a->opt.validate(err)) throw InputError("command line", 0, "approach", err);
    ApproachProblem pb;
    pb.p_start_W = Eigen::Vector3d(a->start[0], a->start[1], a->start[2]);
    pb.stem_xy_W = Eigen::Vector2d(a->stem[0], a->stem[1]);
    pb.fruit_W = Eigen::Vector3d(a->fruit[0], a->fruit[1], a->fruit[2]);
    if (!a->start_cardan.empty())
      pb.cardan_start = Eigen::Vector3d(a->start_cardan[0], a->start_cardan[1], a->start_cardan[2]);
    if (!a->reference.empty())
      pb.reference_xy_W = Eigen::Vector2d(a->reference[0], a->reference[1]);
    const ApproachTrajectory tr = planApproach(pb, a->opt);
    if (tr.status() != ApproachStatus::Ok) {
      std::fprintf(stderr, "armstudy: approach not plannable: %s\n", toString(tr.status()));
      return 3;
    }
    std::ostringstream os;
    os << "t,s,x,y,z,alpha,beta,gamma,xd,yd,zd,alphad,betad,gammad,xdd,ydd,zdd,alphadd,betadd,"
          "gammadd\n";
    const long steps = std::lround(a->opt.duration_s * a->rate_hz);
    for (long k = 0; k <= steps; ++k) {
      const TaskSample w = tr.sample(std::min(a->opt.duration_s, k / a->rate_hz));
      os << formatG(w.t, 12) << ',' << formatG(w.s, 12);
      for (const auto* v : {&w.w, &w.wd, &w.wdd})
        for (int c = 0; c < 6; ++c) os << ',' << formatG((*v)[c], 12);
      os << '\n';
    }
    if (a->out.empty())
      std::fputs(os.str().c_str(), stdout);
    else
      writeFileAtomic(a->out, os.str());
    std::fprintf(stderr, "entry time t_e = %.6f s, goal gamma = %.6f rad\n", tr.entryTime(),
                 tr.goalCardan().z());
    return 0;
  });
}

}  // namespace armstudy::cli
