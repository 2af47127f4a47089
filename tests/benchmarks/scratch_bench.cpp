#include <chrono>
#include <ctime>
static double cpu(){timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t); return t.tv_sec+1e-9*t.tv_nsec;}
#include <cstdio>
#include <cstdlib>
#include <random>
#include "io/design_io.hpp"
#include "ik/reach_solver.hpp"
#include "test_support.hpp"
using namespace armstudy;

int main(int argc, char** argv) {
  const int N = argc > 2 ? atoi(argv[2]) : 2000;
  const Model m = loadDesign(test::sourcePath(argv[1]));
  std::mt19937_64 rng(2024);
  KinematicsWorkspace kin(m);
  IkWorkspace ws(m);
  IkOptions o;
  if (argc > 3) o.max_starts = atoi(argv[3]);
  if (argc > 4) o.max_iterations = atoi(argv[4]);
  o.algorithm = IkAlgorithm::LmOnly;
  long it = 0, st = 0, ok = 0; long it_ok=0, st_ok=0;
  double t0 = cpu();
  for (int k = 0; k < N; ++k) {
    Eigen::VectorXd q = test::randomConfiguration(m, rng);
    forwardKinematics(m, kin, q);
    IkTarget t; t.task_space = TaskSpace::fullPose(); t.w_d = tcpTaskVector(kin).w;
    IkResult r = solvePose(m, ws, t, o, k);
    it += r.iterations; st += r.starts; ok += r.reachable();
    if (r.reachable()) { it_ok += r.iterations; st_ok += r.starts; }
    else if (k < 2000 && getenv("V")) { printf("fail k=%d st=%d it=%d pe=%.2e oe=%.2e margin_true=%.3f status=%s\n", k, r.starts, r.iterations, r.position_error_m, r.orientation_error_rad, jointLimitMargin(m,q), toString(r.status)); }
  }
  double s = cpu()-t0;
  printf("%s solved %.2f%% us/pose %.1f it/pose %.1f starts/pose %.2f | ok: it %.1f starts %.2f\n", m.name.c_str(), 100.0*ok/N, 1e6*s/N, double(it)/N, double(st)/N, double(it_ok)/ok, double(st_ok)/ok);
}
// fk timing
struct FkT { FkT() { if (!getenv("FK")) return; const Model m = loadDesign(test::sourcePath("designs/first_prototype_6dof.toml")); KinematicsWorkspace k(m); std::mt19937_64 r(1); Eigen::VectorXd q = test::randomConfiguration(m, r); double t0=cpu(); double acc=0; for (int i=0;i<1000000;++i){ q[1]+=1e-7; forwardKinematics(m,k,q); acc+=k.p_WT[0]; } double t1=cpu(); IkTarget t; t.task_space=TaskSpace::fullPose(); t.w_d << 0.3,0.5,1,0.1,0.2,0.3; PoseError e; for (int i=0;i<1000000;++i){ q[1]+=1e-7; forwardKinematics(m,k,q); e=poseError(k,t); acc+=e.position_m; } double t2=cpu(); printf("fk %.3f us, fk+err %.3f us (%g)\n", t1-t0, t2-t1, acc); } } fkt;
