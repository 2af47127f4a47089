"""A study run from Python (from its file and from a dict) writes the files of `armstudy run`,
byte for byte (the manifest, which records times, aside), and returns the maps it wrote with
their grid axes, the summary metrics and the per-pose flags."""
import copy
import filecmp
import os
import tempfile
import unittest

import numpy as np

import armstudy
from support import cli, design_path

GRID = {"name": "row", "x": {"from": "-0.7 m", "to": "0.7 m", "step": "0.1 m"},
        "y": {"from": "0.3 m", "to": "1.2 m", "step": "0.1 m"}, "z": "1.2 m",
        "alpha": "0 deg", "gamma": ["-40 deg", "40 deg"]}
DESIGN = "first_prototype_6dof"


def study_dict(name):
    return {"study": {"name": name, "description": "a coarse spraying row"},
            "design": [{"file": design_path(DESIGN)}],
            "reach": {"task_space": "spraying", "position_tolerance": "1 mm",
                      "orientation_tolerance": "0.5 deg", "grid": [copy.deepcopy(GRID)]}}


STUDY_TOML = f"""[study]
name = "py_row"
description = "a coarse spraying row"

[[design]]
file = "{design_path(DESIGN)}"

[reach]
task_space = "spraying"
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"

[[reach.grid]]
name = "row"
x = {{ from = "-0.7 m", to = "0.7 m", step = "0.1 m" }}
y = {{ from = "0.3 m", to = "1.2 m", step = "0.1 m" }}
z = "1.2 m"
alpha = "0 deg"
gamma = ["-40 deg", "40 deg"]
"""


def tree(root):
    out = []
    for folder, _, files in os.walk(root):
        out += [os.path.relpath(os.path.join(folder, f), root) for f in files]
    return sorted(f for f in out if f != "manifest.json")


class Study(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.study = os.path.join(self.dir, "py_row.toml")
        with open(self.study, "w") as f:
            f.write(STUDY_TOML)

    def tearDown(self):
        self.tmp.cleanup()

    def assertSameFiles(self, a, b):
        fa, fb = tree(a), tree(b)
        self.assertEqual(fa, fb)
        self.assertGreater(len(fa), 3)
        for f in fa:
            self.assertTrue(filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False), f)

    def test_file_and_dict_studies_write_the_cli_bytes(self):
        cli("run", self.study, "--output", os.path.join(self.dir, "cli"), "--threads", "2")
        r = armstudy.run_study(self.study, output=os.path.join(self.dir, "py"), threads=2)
        self.assertSameFiles(os.path.join(self.dir, "cli", "py_row"), r["output_dir"])
        d = armstudy.run_study(study_dict("py_row"), output=os.path.join(self.dir, "dict"), threads=1)
        self.assertSameFiles(os.path.join(self.dir, "cli", "py_row"), d["output_dir"])
        self.assertEqual(r["metrics"], d["metrics"])

        # The map: grid axes of the study, statuses with their names, and the reachable flags the
        # stage reported agree with the status arrays read back from the file.
        self.assertIn("reach/row/" + DESIGN + ".vti", r["maps"])
        m = r["maps"]["reach/row/" + DESIGN + ".vti"]
        np.testing.assert_allclose(m["axes"]["x"], np.arange(-0.7, 0.7 + 1e-9, 0.1), atol=1e-12)
        np.testing.assert_allclose(m["axes"]["y"], np.arange(0.3, 1.2 + 1e-9, 0.1), atol=1e-12)
        self.assertEqual(m["dims"], (15, 10, 1))
        status = [k for k in m["arrays"] if k.startswith("status")]
        self.assertEqual(len(status), 2)  # one per orientation
        self.assertEqual(m["arrays"][status[0]].shape, (1, 10, 15))
        self.assertEqual(status, ["status_o0", "status_o1"])
        self.assertTrue(m["names"]["status"][0].startswith("reachable"), m["names"])
        self.assertTrue(m["names"]["status"][1].startswith("out_of_reach"), m["names"])
        flags = r["flags"][f"reach/row/{DESIGN}/reachable"]
        from_map = np.concatenate([(m["arrays"][s] == 0).ravel() for s in status])
        np.testing.assert_array_equal(from_map, flags.astype(bool))
        self.assertAlmostEqual(r["metrics"][f"reach/row/{DESIGN}/reachable_fraction"], flags.mean(), places=15)
        self.assertTrue(0 < flags.mean() < 1)

    def test_a_dict_error_names_the_key_path(self):
        bad = study_dict("bad")
        bad["reach"]["grid"][0]["x"]["step"] = "-0.1 m"
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.run_study(bad, output=os.path.join(self.dir, "bad"))
        self.assertEqual(e.exception.file, "study dict")
        self.assertEqual(e.exception.line, 0)
        self.assertTrue(e.exception.key.startswith("reach.grid[0].x"), e.exception.key)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "bad")))

    def test_a_missing_key_is_named_as_the_cli_names_it(self):
        bad = study_dict("missing")
        del bad["reach"]["grid"][0]["x"]["step"]
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.check_study(bad)
        self.assertEqual(e.exception.key, "reach.grid[0].x.step")
        self.assertIn("missing required key", e.exception.message)


if __name__ == "__main__":
    unittest.main()
