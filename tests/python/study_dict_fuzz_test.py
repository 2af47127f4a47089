"""Mutation fuzzing of study dicts: shipped studies read into dicts (tomllib), with seeded
mutations (values replaced by None, NaN, huge integers, wrong types, hostile strings, nested lists
and dicts, deep nesting, self-references; keys deleted or added), each checked with
armstudy.check_study, which reads and validates a study dict exactly as run_study does before any
work. Every call either returns or raises armstudy.InputError: another exception is a failure, and
the loop runs in a child process (support.run_isolated) so that a crash fails the test too."""
import copy
import math
import os
import random
import reprlib
import tomllib
import unittest

import armstudy
from support import SOURCE_DIR, run_isolated

STUDIES_DIR = os.path.join(SOURCE_DIR, "studies")
# Studies whose designs and data load in milliseconds (no URDF meshes to fit).
STUDIES = ["spraying_row", "default", "base_placement", "compare_designs", "explore_final_prototype",
           "fig5_13_obstacle", "harvest_torque", "regression", "stem_ellipsoids", "stem_heatmap",
           "stem_obstacles", "stem_row", "thesis_drive_friction", "arm_calibration"]
SEEDS = [1, 2]
CALLS = 400  # per seed: a fixed count, so that a run checks the same mutations on any machine
CHILD_MEMORY_BYTES = 3 << 30  # a runaway allocation fails in the child instead of swapping

HOSTILE_VALUES = [
    None, math.nan, math.inf, -math.inf, 2**64, -2**63 - 1, 10**400, 2**53 + 1, 1e308, -1e308,
    5e-324, 0, -1, 0.0, True, False, "", "\x00", "nan m", "1e999 m", "-pi/0", "1/0 deg", "x" * 5000,
    "../../../../etc/passwd", "/dev/zero", "\ud800", [], {}, [None], {"": None}, (1, 2), b"bytes",
    object(), 1j, {"from": 0, "to": 1e300, "step": 1e-300},
]


def deep(kind, depth, leaf):
    for _ in range(depth):
        leaf = [leaf] if kind == "list" else {"k": leaf}
    return leaf


def slots(node, out, seen=None, depth=0):
    """Every (container, key) of the nested dicts and lists under node, each container once and
    at most 20 levels deep (earlier mutations leave self-references and deep nesting behind)."""
    seen = set() if seen is None else seen
    if id(node) in seen or depth > 20:
        return out
    seen.add(id(node))
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in list(items):
        out.append((node, key))
        if isinstance(value, (dict, list)):
            slots(value, out, seen, depth + 1)
    return out


def mutate(rng, root):
    """Applies one seeded mutation to root in place; returns its description."""
    container, key = rng.choice(slots(root, []))
    value = container[key]
    op = rng.randrange(9)
    if op <= 2:
        new = copy.deepcopy(rng.choice(HOSTILE_VALUES))
    elif op == 3:
        new = deep(rng.choice(["list", "dict"]), rng.choice([100, 255, 256, 257, 300, 5000]), value)
    elif op == 4:
        new = rng.choice([root, container])  # a self-reference
    elif op == 5:
        new = rng.choice([[value], {"k": value}, [value, value], [value] * 1000])
    elif op == 6:
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            new = value * rng.choice([-1, 1e6, 1e-6, 1e300, 10**30])
        else:
            new = reprlib.repr(value)[:50] + rng.choice([" m", " deg", "\"", "'''", "\n[x]", "]]"])
    elif op == 7:
        if isinstance(container, dict):
            del container[key]
            return f"deleted {key!r}"
        container.append(value)
        return "appended the entry again"
    else:
        target = container if isinstance(container, dict) else root
        target[rng.choice(["unknown", "", "a.b", "\x00", "[x]"])] = copy.deepcopy(rng.choice(HOSTILE_VALUES))
        return "added a key"
    container[key] = new
    return f"{key!r} -> {type(new).__name__} {reprlib.repr(new)[:60]}"


def fuzz(seed, calls):
    """The loop the child runs: returns counts and the failures (call, exception)."""
    rng = random.Random(seed)
    originals = {}
    for name in STUDIES:
        with open(os.path.join(STUDIES_DIR, name + ".toml"), "rb") as f:
            originals[name] = tomllib.load(f)
        armstudy.check_study(originals[name], folder=STUDIES_DIR)  # unmutated: loads
    counts = {"calls": 0, "returned": 0, "input_errors": 0}
    failures = []
    for _ in range(calls):
        name = rng.choice(STUDIES)
        study = copy.deepcopy(originals[name])
        steps = [mutate(rng, study) for _ in range(rng.randint(1, 3))]
        counts["calls"] += 1
        try:
            armstudy.check_study(study, folder=STUDIES_DIR)
            counts["returned"] += 1
        except armstudy.InputError:
            counts["input_errors"] += 1
        except BaseException as e:  # noqa: B902  (anything else is the finding)
            failures.append(f"{name}: {steps}: {type(e).__name__}: {str(e)[:200]}")
    return {"counts": counts, "failures": failures}


class StudyDictFuzz(unittest.TestCase):
    def test_mutated_study_dicts_load_or_raise_input_error(self):
        for seed in SEEDS:
            result = run_isolated(f"import study_dict_fuzz_test as t\n"
                                  f"print(json.dumps(t.fuzz({seed}, {CALLS})))",
                                  memory_bytes=CHILD_MEMORY_BYTES)
            counts = result["counts"]
            self.assertEqual(result["failures"], [], f"seed {seed}")
            self.assertEqual(counts["calls"], CALLS, counts)
            self.assertGreater(counts["input_errors"], 0, counts)
            self.assertGreater(counts["returned"], 0, counts)


if __name__ == "__main__":
    unittest.main()
