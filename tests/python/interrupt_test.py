"""Ctrl-C during run_study: a child python runs a study of several seconds, SIGINT arrives after
about 1.5 s, the child must raise KeyboardInterrupt within 1 s of it (timed on the system-wide
monotonic clock), leave the output folder unfinished but resumable (no manifest, the saved units
in .partial), and a second run_study must resume it (units loaded, not computed) and write the
same maps as an uninterrupted run. A study that ends before the signal fails the test."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

import armstudy
from support import design_path

STUDY = {"study": {"name": "interrupted"},
         "design": [{"file": design_path("final_prototype_9dof")}],
         "reach": {"task_space": "spraying", "grid": [{"name": "row",
                   "x": {"from": "-0.8 m", "to": "0.8 m", "step": "0.02 m"},
                   "y": {"from": "0.3 m", "to": "1.2 m", "step": "0.02 m"}, "z": "1.2 m",
                   "alpha": "0 deg", "gamma": [f"{g} deg" for g in range(-40, 41, 10)]}]}}

CHILD = """
import json, sys, time
import armstudy
study, out = json.loads(sys.argv[1]), sys.argv[2]
print("started", flush=True)
try:
    armstudy.run_study(study, output=out, threads=2)
    print(json.dumps({"finished": time.monotonic()}), flush=True)
except KeyboardInterrupt:
    print(json.dumps({"interrupted": time.monotonic()}), flush=True)
"""


class Interrupt(unittest.TestCase):
    def test_sigint_raises_keyboard_interrupt_and_the_folder_resumes(self):
        with tempfile.TemporaryDirectory() as out:
            p = subprocess.Popen([sys.executable, "-c", CHILD, json.dumps(STUDY), out],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            try:
                self.assertEqual(p.stdout.readline().strip(), "started")
                time.sleep(1.5)
                sent = time.monotonic()
                p.send_signal(signal.SIGINT)
                stdout, stderr = p.communicate(timeout=60)
            finally:
                if p.poll() is None:
                    p.kill()
                    p.wait()
            lines = [l for l in stdout.splitlines() if l.startswith("{")]
            self.assertTrue(lines, f"child printed no outcome; exit {p.returncode}; {stderr[-2000:]}")
            outcome = json.loads(lines[-1])
            self.assertNotIn("finished", outcome, "the study ended before the signal: make it longer")
            self.assertIn("interrupted", outcome)
            latency = outcome["interrupted"] - sent
            print(f"KeyboardInterrupt {latency:.3f} s after SIGINT", file=sys.stderr)
            self.assertGreaterEqual(latency, 0.0)
            self.assertLess(latency, 1.0)

            folder = os.path.join(out, "interrupted")
            self.assertFalse(os.path.exists(os.path.join(folder, "manifest.json")))
            units = os.listdir(os.path.join(folder, ".partial", "units"))
            self.assertTrue(units, "no unit was saved before the interrupt")

            resumed = armstudy.run_study(STUDY, output=out, threads=2)
            self.assertGreater(resumed["units_resumed"], 0)
            self.assertTrue(resumed["resume_message"].startswith("resuming"), resumed["resume_message"])
            self.assertTrue(os.path.isfile(os.path.join(folder, "manifest.json")))
            fresh = armstudy.run_study(dict(STUDY, study={"name": "fresh"}), output=out, threads=2)
            self.assertEqual(fresh["units_resumed"], 0)
            for f, m in fresh["maps"].items():
                for a, v in m["arrays"].items():
                    np.testing.assert_array_equal(resumed["maps"][f]["arrays"][a], v, err_msg=f"{f} {a}")


if __name__ == "__main__":
    unittest.main()
