"""No memory growth over 10^5 calls: the resident set size after 10^5 single-configuration calls
(the kernels in turn, pose solves and batches among them) and after 10^4 raised exceptions stays
within a small allowance of the size after a warm-up of the same calls."""
import unittest

import numpy as np

import armstudy
from support import design_path, random_configurations

CALLS = 100_000
WARM_UP = 2_000
# Growth allowed after the warm-up: allocator noise, far below what a leak of even 16 bytes per
# call (1.6 MB over 10^5 calls) would add.
ALLOWED_GROWTH_KB = 512


def rss_kb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS in /proc/self/status")


class Memory(unittest.TestCase):
    def measure(self, call, count):
        for i in range(WARM_UP):
            call(i)
        before = rss_kb()
        for i in range(count):
            call(i)
        return rss_kb() - before

    def test_kernels_do_not_grow(self):
        d = armstudy.load_design(design_path("final_prototype_7dof"))
        q = random_configurations(d, 64, seed=21)
        pose = np.array([0.2, 0.8, 1.0, 0.0, 0.0, 0.3])

        calls = [lambda qi: d.fk(qi), lambda qi: d.jacobian(qi), lambda qi: d.manipulability(qi),
                 lambda qi: d.inverse_dynamics(qi), lambda qi: d.self_distances(qi)]

        def kernels(i):
            calls[i % len(calls)](q[i % 64])
            if i % 500 == 0:
                d.solve(pose, pose_id=i)
                d.fk(q, threads=2)

        growth = self.measure(kernels, CALLS)
        print(f"RSS growth over {CALLS} kernel calls: {growth} kB")
        self.assertLess(growth, ALLOWED_GROWTH_KB)

    def test_exceptions_do_not_grow(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))

        def bad(i):
            try:
                d.with_entries({"joint.nope.z": 1.0})
            except armstudy.InputError:
                pass
            try:
                d.fk([0.0])
            except ValueError:
                pass

        growth = self.measure(bad, CALLS // 10)
        print(f"RSS growth over {CALLS // 10} raised exceptions: {growth} kB")
        self.assertLess(growth, ALLOWED_GROWTH_KB)


if __name__ == "__main__":
    unittest.main()
