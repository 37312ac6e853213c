# SPDX-License-Identifier: GPL-3.0-or-later
"""The criteria of the CAD corpus benchmark (Testing/Benchmarks/cad_corpus.py), the one
implementation behind the corpus run and the ctest cases (label cad-corpus): verdicts on
made-up facts and conversion summaries, and the cases file's format."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Benchmarks"))
import cad_corpus  # noqa: E402

FACTS = {"faces": 12, "closed": True, "non_manifold_edges": 0, "read_time": 2.0}


def summary(**changes):
    s = {"exit_status": 0, "error": None, "options": {"tolerance": 1e-4}, "faces": 12,
         "diagonal": 10.0, "free_edges": 0, "non_manifold_edges": 0,
         "extra_non_manifold_edges": 0, "c0_gap": 0.0,
         "max_deviation": 9e-5, "edge_gap": 1e-4, "tangent_edges": 8,
         "g1_angle_tangent": 0.05, "max_normal_deviation": 0.2, "rms_normal_deviation": 0.05}
    s.update(changes)
    return s


def run(s=None, **changes):
    r = {"exit_status": 0, "signal": 0, "timed_out": False, "traceback": False,
         "error_line": "", "wall": 3.0, "summary": summary() if s is None else s}
    r.update(changes)
    return r


def verdicts(facts, r):
    return {name: passed for name, (passed, _) in cad_corpus.evaluate(facts, r).items()}


class CriteriaTest(unittest.TestCase):
    def test_a_good_conversion_passes_everything(self):
        v = verdicts(FACTS, run())
        self.assertEqual(v, {name: True for name in cad_corpus.CRITERION_NAMES})
        self.assertTrue(cad_corpus.overall(cad_corpus.evaluate(FACTS, run())))

    def test_each_guarantee_fails_on_its_own_figure(self):
        for key, value, criterion in (
                ("free_edges", 3, "free_edges"), ("extra_non_manifold_edges", 8, "non_manifold"),
                ("c0_gap", 1e-12, "c0_gap"), ("max_deviation", 1.1e-4, "deviation"),
                ("g1_angle_tangent", 0.2, "g1"), ("g1_angle_tangent", 177.0, "g1_flip")):
            v = verdicts(FACTS, run(summary(**{key: value})))
            self.assertFalse(v[criterion], (key, value))
            self.assertEqual([n for n, ok in v.items() if not ok],
                             [criterion] if criterion != "g1_flip" else ["g1", "g1_flip"])

    def test_bounds_that_depend_on_the_model(self):
        # The model's own edge gap: up to twice it (relative to the diagonal) is allowed.
        self.assertTrue(verdicts(FACTS, run(summary(edge_gap=1e-3, max_deviation=1.9e-4)))
                        ["deviation"])
        self.assertFalse(verdicts(FACTS, run(summary(edge_gap=1e-3, max_deviation=2.1e-4)))
                         ["deviation"])
        # Non-manifold edges the B-rep has itself are not the conversion's; others are, even
        # where the B-rep has some.
        self.assertTrue(verdicts(dict(FACTS, non_manifold_edges=2),
                                 run(summary(non_manifold_edges=8)))["non_manifold"])
        self.assertFalse(verdicts(dict(FACTS, non_manifold_edges=2),
                                  run(summary(non_manifold_edges=9, extra_non_manifold_edges=1)))
                         ["non_manifold"])
        # No tangent interface: nothing to be G1.
        v = verdicts(FACTS, run(summary(tangent_edges=0, g1_angle_tangent=None)))
        self.assertTrue(v["g1"] and v["g1_flip"])
        # Time: 1.5 x OCCT's read time + 1 s.
        self.assertTrue(verdicts(FACTS, run(wall=4.0))["time"])
        self.assertFalse(verdicts(FACTS, run(wall=4.01))["time"])
        self.assertIsNone(verdicts({"error": "unreadable"}, run())["time"])

    def test_missing_keys_are_not_reported(self):
        s = summary()
        del s["max_normal_deviation"], s["c0_gap"]
        results = cad_corpus.evaluate(FACTS, run(s))
        self.assertEqual(results["normal_deviation"], (False, "not reported"))
        self.assertEqual(results["c0_gap"], (False, "c0_gap not reported"))

    def test_how_a_conversion_may_fail(self):
        error = {"exit_status": 1, "error": "face 3: empty parameter domain"}
        v = verdicts(FACTS, run(error, exit_status=1, error_line="error: face 3: empty"))
        self.assertTrue(v["converts"])  # a clear error
        self.assertFalse(v["free_edges"] or v["deviation"])  # but no conversion
        for changes in ({"timed_out": True, "exit_status": -9}, {"signal": 11, "exit_status": -11},
                        {"traceback": True, "exit_status": 1, "error_line": "error: x"},
                        {"exit_status": 1}):
            self.assertFalse(verdicts(FACTS, run(None, **changes))["converts"], changes)

    def test_cases_file(self):
        here = os.path.dirname(os.path.abspath(__file__))
        cases = cad_corpus.read_cases(os.path.join(here, "..", "Benchmarks",
                                                   "cad_corpus_cases.txt"))
        self.assertGreaterEqual(len(cases), 20)
        with tempfile.NamedTemporaryFile("w", suffix=".txt") as f:
            f.write("# comment\na occt-misc x.step guarantees deviation\n"
                    "b gmsh-doc y.step.gz\n    converts,c0_gap skip\n")
            f.flush()
            cases = cad_corpus.read_cases(f.name)
            self.assertEqual(cases["a"]["xfail"], ("deviation",))
            self.assertNotIn("time", cases["a"]["criteria"])
            self.assertEqual(cases["b"]["criteria"], ("converts", "c0_gap"))
            self.assertTrue(cases["b"]["skip"])
            f.write("c occt-misc z.step all no_such_criterion\n")
            f.flush()
            with self.assertRaises(ValueError):
                cad_corpus.read_cases(f.name)


if __name__ == "__main__":
    unittest.main()
