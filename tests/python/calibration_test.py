"""The model-versus-measurement loop: synthesized TCP poses are the CLI's `synth` CSV byte for
byte; compare and fit on the arrays (and on the drive test bed of thesis chapter 4) give the CLI's
result.json numbers (the same engine), rank the hidden effect first and recover its value within
the 95 % interval."""
import json
import os
import tempfile
import unittest

import numpy as np

import armstudy
from support import SOURCE_DIR, cli, design_path

DESIGN = "final_prototype_7dof"
HIDDEN_OFFSET_RAD = 0.004


class Calibration(unittest.TestCase):
    def test_fit_on_arrays_equals_the_cli_and_finds_the_hidden_effect(self):
        d = armstudy.load_design(design_path(DESIGN))
        hidden = f"joint_offset.j3:offset={HIDDEN_OFFSET_RAD}"
        s = armstudy.synthesize_tcp(d, rows=60, hidden=[hidden], seed=5)
        self.assertEqual(s["q"].shape, (60, d.dof))
        self.assertEqual(s["pose"].shape, (60, 3))
        with tempfile.TemporaryDirectory() as tmp:
            csv = os.path.join(tmp, "tcp.csv")
            cli("synth", design_path(DESIGN), "--kind", "tcp", "--rows", "60", "--hide", hidden,
                "--seed", "5", "--out", csv)
            with open(csv) as f:
                self.assertEqual(f.read(), s["csv"])
            cli("fit", design_path(DESIGN), "--kind", "tcp", "--data", csv, "--auto", "--out",
                os.path.join(tmp, "fit"))
            with open(os.path.join(tmp, "fit", "result.json")) as f:
                j = json.load(f)
            from_file = armstudy.fit(d, csv, auto=True)
        r = armstudy.fit(d, s["q"], pose=s["pose"], auto=True)
        for result in (r, from_file):
            self.assertEqual(result["verdict"], j["verdict"])
            self.assertEqual(result["rmse_before"], j["rmse_before"])
            self.assertEqual(result["rmse_after"], j["rmse_after"])
            self.assertEqual(result["noise_estimate"], j["noise_estimate"])
            self.assertEqual([c["name"] for c in result["ranking"]], [c["effect"] for c in j["ranking"]])
            self.assertEqual([c["improvement"] for c in result["ranking"]],
                             [c["improvement"] for c in j["ranking"]])
            self.assertEqual([f["heldout_rmse"] for f in result["ladder"]],
                             [f["heldout_rmse"] for f in j["ladder"]])
            self.assertEqual(result["final"]["params"], j["final_params"])
        self.assertEqual(r["ranking"][0]["name"], "joint_offset.j3")
        p = r["final"]["params"][0]
        self.assertEqual(p["key"], "joint_offset.j3.offset")
        self.assertLessEqual(p["ci_low"], HIDDEN_OFFSET_RAD)
        self.assertLessEqual(HIDDEN_OFFSET_RAD, p["ci_high"])
        # The final model's residual is the measurement minus its prediction.
        np.testing.assert_allclose(r["final"]["residual"], r["measured"] - r["final"]["predicted"], atol=1e-15)

    def test_compare_only_and_errors(self):
        d = armstudy.load_design(design_path(DESIGN))
        s = armstudy.synthesize_tcp(d, rows=40, seed=6)
        c = armstudy.compare(d, s["q"], pose=s["pose"])
        self.assertEqual([f["label"] for f in c["ladder"]], ["as designed"])
        self.assertLess(c["as_designed"]["train_rmse"], 5e-4)   # noise of 0.1 mm only
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.fit(d, s["q"], pose=s["pose"], add=["no_such_effect"])
        self.assertIn("no_such_effect", str(e.exception))
        with self.assertRaises(ValueError):
            armstudy.fit(d, s["q"], pose=s["pose"][:10])


    def test_drive_kind_equals_the_cli(self):
        # Thesis chapter 4: drive j6 of the final 9-DoF prototype against the module B.2 test bed.
        design = design_path("final_prototype_9dof")
        data = os.path.join(SOURCE_DIR, "studies", "data", "drive_testbed_module_b2.csv")
        with tempfile.TemporaryDirectory() as tmp:
            cli("fit", design, "--drive", "j6", "--data", data, "--auto", "--out", tmp)
            with open(os.path.join(tmp, "result.json")) as f:
                j = json.load(f)
        r = armstudy.fit(armstudy.load_design(design), data, kind="drive", joint="j6", auto=True)
        self.assertEqual(r["verdict"], j["verdict"])
        self.assertEqual((r["rmse_before"], r["rmse_after"]), (j["rmse_before"], j["rmse_after"]))
        self.assertEqual([f["label"] for f in r["ladder"]], [f["label"] for f in j["ladder"]])
        self.assertEqual(r["final"]["params"], j["final_params"])
        self.assertIn("stribeck", r["verdict"])
        with self.assertRaises(armstudy.InputError):
            armstudy.fit(armstudy.load_design(design), data, kind="drive", joint="j99")


if __name__ == "__main__":
    unittest.main()
