"""The typed stub beside the module names exactly the module's functions and Design's members, and
every one of them has a docstring; batch calls release the GIL (another Python thread runs
while a batch solves)."""
import ast
import os
import threading
import time
import unittest

import numpy as np

import armstudy
from support import design_path


def stub_names():
    path = os.path.join(os.path.dirname(armstudy.__file__), "armstudy.pyi")
    tree = ast.parse(open(path).read())
    functions = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    design = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Design")
    members = {n.name for n in design.body if isinstance(n, ast.FunctionDef)}
    return functions, members


class Api(unittest.TestCase):
    def test_stub_matches_the_module(self):
        functions, members = stub_names()
        module = {n for n in dir(armstudy) if callable(getattr(armstudy, n)) and not n.startswith("_")
                  and n[0].islower()}
        self.assertEqual(functions, module)
        design = {n for n in dir(armstudy.Design) if not n.startswith("_")}
        self.assertEqual(members, design)
        for n in module:
            self.assertTrue(getattr(armstudy, n).__doc__, n)

    def test_batches_release_the_gil(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        rng = np.random.default_rng(31)
        n = 8000
        poses = np.column_stack([rng.uniform(-0.6, 0.6, n), rng.uniform(0.4, 1.0, n), np.full(n, 1.0),
                                 np.zeros(n), np.zeros(n), np.zeros(n)])
        span = {}
        done = threading.Event()

        def batch():
            span["start"] = time.perf_counter()
            d.solve_batch(poses, threads=1)
            span["end"] = time.perf_counter()
            done.set()

        t = threading.Thread(target=batch)
        t.start()
        ticks = []
        while not done.is_set():
            ticks.append(time.perf_counter())
        t.join()
        inside = [x for x in ticks if span["start"] <= x <= span["end"]]
        edges = [span["start"], *inside, span["end"]]
        longest_gap = max(b - a for a, b in zip(edges, edges[1:]))
        # With the GIL held through the batch, this thread would not run until it ends.
        self.assertLess(longest_gap, (span["end"] - span["start"]) / 2)


if __name__ == "__main__":
    unittest.main()
