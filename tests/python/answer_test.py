"""StudyResult.answer() returns report.md's answer block: the Answer and Warnings sections and the
Assumptions the results rest on, and nothing of the sections after it (Designs, Details); the
notebook display shows the same block. Checked against the report.md the run wrote, split at its
level-2 headings here."""
import copy
import os
import tempfile
import unittest

import armstudy
from support import design_path

ASSUMED = "The row stands 0.7 m in front of the arm (row_y): chosen for this test."
STUDY = {"study": {"name": "py_answer", "description": "a coarse spraying row",
                   "question": "Which share of the row can the arm spray?",
                   "assumptions": [ASSUMED]},
         "design": [{"file": design_path("first_prototype_6dof")}],
         "reach": {"task_space": "spraying", "position_tolerance": "1 mm",
                   "orientation_tolerance": "0.5 deg",
                   "grid": [{"name": "row", "x": {"from": "-0.5 m", "to": "0.5 m", "step": "0.25 m"},
                             "y": "0.7 m", "z": "1.2 m", "alpha": "0 deg", "gamma": "0 deg"}]}}


def sections(text):
    """report.md's level-2 sections in order: (heading, text from the heading to the next)."""
    out, at = [], text.find("## ")
    while at >= 0:
        nxt = text.find("\n## ", at + 1)
        out.append((text[at:text.find("\n", at)], text[at:] if nxt < 0 else text[at:nxt]))
        at = -1 if nxt < 0 else nxt + 1
    return out


class Answer(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def run_study(self, study):
        r = armstudy.run_study(study, output=self.tmp.name, threads=2)
        with open(os.path.join(r["output_dir"], "report.md"), encoding="utf-8") as f:
            return r, sections(f.read())

    def test_the_answer_block_holds_the_assumptions_and_stops_before_the_designs(self):
        r, parts = self.run_study(STUDY)
        heads = [h for h, _ in parts]
        self.assertEqual(heads[:4], ["## Answer", "## Warnings", "## Assumptions", "## Designs"])
        got = r.answer()
        self.assertEqual(got, "".join(t + "\n" for _, t in parts[:3])[:-1])
        self.assertIn(ASSUMED, got)
        self.assertNotIn("## Designs", got)
        self.assertNotIn("## Details", got)
        shown = r._repr_html_()
        self.assertIn("<h4>Assumptions</h4>", shown)
        self.assertIn("row_y", shown)
        self.assertNotIn("Designs", shown)

    def test_without_assumptions_the_block_ends_after_the_warnings(self):
        study = copy.deepcopy(STUDY)
        study["study"]["name"] = "py_answer_plain"
        del study["study"]["assumptions"]
        r, parts = self.run_study(study)
        heads = [h for h, _ in parts]
        self.assertNotIn("## Assumptions", heads)
        self.assertEqual(heads[:3], ["## Answer", "## Warnings", "## Designs"])
        self.assertEqual(r.answer(), "".join(t + "\n" for _, t in parts[:2])[:-1])


if __name__ == "__main__":
    unittest.main()
