"""Every bad input raises armstudy.InputError with the message the CLI prints on exit 2 (file,
line, key); bad arrays raise ValueError before any C++ check could end the process."""
import os
import tempfile
import unittest

import numpy as np

import armstudy
from support import ROBOTS_DIR, cli, design_path

TWO_JOINTS = """[design]
name = "two"

[[joint]]
name = "j1"
type = "revolute"
x = 0
y = 0
z = 0.5
alpha = 0
beta = 0
gamma = 0
min = "-90 deg"
max = "90 deg"

[[joint]]
name = "j2"
type = "revolute"
x = 0.4
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = "-90 deg"
max = {max}

[tcp]
x = 0.2
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
"""


class Errors(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def assertCliMessage(self, error, *args):
        code, _, err = cli(*args, check=False)
        self.assertEqual(code, 2, err)
        self.assertEqual(err.strip(), "armstudy: error: " + str(error))

    def test_design_errors_carry_the_cli_message(self):
        missing = os.path.join(self.tmp.name, "missing.toml")
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.load_design(missing)
        self.assertEqual(e.exception.file, missing)
        self.assertCliMessage(e.exception, "describe", missing)

        bad = self.write("bad.toml", TWO_JOINTS.format(max='"90 parsecs"'))
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.load_design(bad)
        self.assertEqual((e.exception.file, e.exception.line), (bad, 26))  # the line of j2's max
        self.assertIn("max", e.exception.key)
        self.assertIn(e.exception.message, str(e.exception))
        self.assertCliMessage(e.exception, "describe", bad)
        self.assertIsInstance(e.exception, ValueError)

        with self.assertRaises(armstudy.InputError) as e:
            armstudy.parse_design(TWO_JOINTS.format(max='"90 parsecs"'), "my text")
        self.assertEqual(e.exception.file, "my text")

    def test_urdf_errors_carry_the_cli_message(self):
        ur5 = os.path.join(ROBOTS_DIR, "ur_description", "urdf", "ur5_robot.urdf")
        self.assertTrue(os.path.isfile(ur5), ur5)
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.load_design(ur5, base="base_link", tip="no_such_link", collision=False)
        self.assertCliMessage(e.exception, "describe", ur5, "--base", "base_link", "--tip", "no_such_link",
                              "--no-collision")
        d = armstudy.load_design(ur5, base="base_link", tip="tool0", collision=False)
        self.assertEqual(d.dof, 6)

    def test_study_errors_carry_the_cli_message(self):
        study = self.write("s.toml", '[study]\nname = "s"\n\n[[design]]\nfile = "nowhere.toml"\n')
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.run_study(study, output=os.path.join(self.tmp.name, "out"))
        self.assertCliMessage(e.exception, "run", study, "--output", os.path.join(self.tmp.name, "out"))
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "out")))

    def test_dynamics_without_inertia(self):
        d = armstudy.parse_design(TWO_JOINTS.format(max='"90 deg"'))
        with self.assertRaises(armstudy.InputError) as e:
            d.inverse_dynamics([0.0, 0.0])
        path = self.write("two.toml", TWO_JOINTS.format(max='"90 deg"'))
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.load_design(path).inverse_dynamics([0.0, 0.0])
        self.assertCliMessage(e.exception, "dynamics", path, "--q", "0,0")

    def test_variant_entries(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        v = d.with_entries({"joint.j2.z": -0.2}, name="lower_j2")
        self.assertEqual((v.name, v.joints[1]["z"]), ("lower_j2", -0.2))
        self.assertEqual(d.joints[1]["z"], -0.1)
        with self.assertRaises(armstudy.InputError) as e:
            d.with_entries({"joint.nope.z": 1.0})
        self.assertEqual(e.exception.key, "joint.nope.z")

    def test_bad_arrays_raise_value_error(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        for q in ([0.0] * 5, np.zeros((3, 7)), np.zeros((2, 3, 6)), [0, 0, np.nan, 0, 0, 0], "abc"):
            with self.assertRaises(ValueError):
                d.fk(q)
        with self.assertRaises(ValueError):
            d.manipulability(np.zeros(6), "x,y,w")
        with self.assertRaises(ValueError):
            d.fk(np.zeros(6), threads=-1)
        with self.assertRaises(ValueError):
            d.solve_batch(np.zeros((4, 6)), pose_ids=[1, 2])
        with self.assertRaises(ValueError):
            d.inverse_dynamics(np.zeros((2, 6)), np.zeros((3, 6)))
        two = armstudy.parse_design(TWO_JOINTS.format(max='"90 deg"'))
        with self.assertRaises(ValueError):
            two.self_distances([0.0, 0.0])


if __name__ == "__main__":
    unittest.main()
