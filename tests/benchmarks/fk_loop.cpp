// The C++ peer of the Python benchmark (python_bench.py): forward kinematics of the configurations
// in a raw float64 file (N x dof, row-major) in an OpenMP loop with one workspace per thread,
// writing each TCP transform into an N x 16 array as the Python module's fk does. Prints the
// median time of the whole loop and of one configuration on one thread [s].
//   fk_loop DESIGN CONFIGURATIONS.f64 THREADS
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "io/design_io.hpp"
#include "kinematics/kinematics.hpp"

using namespace armstudy;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: fk_loop DESIGN CONFIGURATIONS.f64 THREADS\n");
    return 2;
  }
  const Model m = loadDesign(argv[1]);
  const int threads = std::stoi(argv[3]);
  std::ifstream in(argv[2], std::ios::binary | std::ios::ate);
  const long n = static_cast<long>(in.tellg()) / (8 * m.dof());
  in.seekg(0);
  std::vector<double> q(static_cast<std::size_t>(n) * m.dof()), out(16 * n);
  in.read(reinterpret_cast<char*>(q.data()), static_cast<std::streamsize>(q.size() * 8));
  auto loop = [&](int) {
#pragma omp parallel num_threads(threads)
    {
      KinematicsWorkspace ws(m);
#pragma omp for schedule(static)
      for (long i = 0; i < n; ++i) {
        forwardKinematics(m, ws,
                          Eigen::Map<const Eigen::VectorXd>(q.data() + i * m.dof(), m.dof()));
        double* o = out.data() + 16 * i;
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) o[r * 4 + c] = ws.R_WT(r, c);
          o[r * 4 + 3] = ws.p_WT[r];
        }
        o[12] = o[13] = o[14] = 0.0;
        o[15] = 1.0;
      }
    }
    bench::doNotOptimize(out[16 * (n - 1) + 3]);
  };
  const double batch_s = bench::timePerCall(loop, 1, 15);
  KinematicsWorkspace ws(m);
  const double one_s = bench::timePerCall(
      [&](int i) {
        forwardKinematics(m, ws,
                          Eigen::Map<const Eigen::VectorXd>(q.data() + (i % n) * m.dof(), m.dof()));
        bench::doNotOptimize(ws.p_WT[0]);
      },
      100000);
  std::printf("%.9g %.9g\n", batch_s, one_s);
  return 0;
}
