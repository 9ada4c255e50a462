"""The reference policy from Python (studies/reference_policy.hpp, through flexref.converge
and flexref.work_precision): on book_toss the double reference cannot certify NMB's three finest
of eight levels (estimated error 1.5e-7, so certifying needs an error of 1.5e-5, against errors
of 1.4e-5 down to 8.2e-7; the estimate was 3.7e-8 and two levels before issue 51's error
weights, whose CVODE check at rtol 1e-14 sits at its tolerance floor), and precision="auto"
repeats the study against a quad-precision reference, as `flexref converge` and
`flexref work-precision` do. Run by ctest with PYTHONPATH=build/python from the repository
root."""
import unittest

import flexref


class ReferencePolicyTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scene = flexref.load_scene("scenes/book_toss.toml", model="lte")

    def converge(self, **kwargs):
        return flexref.converge(self.scene, ["nmb"], dt=1e-2, levels=8, jobs=2, **kwargs)

    def test_auto_retries_with_a_quad_reference(self):
        out = self.converge(precision="auto")
        self.assertEqual(out["reference_precision"], "quad")
        self.assertIn("could not certify 3 level(s): the study was repeated with a "
                      "quad-precision reference", out["notes"][0])
        self.assertEqual([lv["status"] for lv in out["levels"]], ["ok"] * 8)
        # A quad reference's estimate is far below double's 1.5e-7 (3.7e-24 measured); 1e-15
        # is below anything a double reference can certify (round-off ~1e-16 x the scale).
        self.assertLess(out["reference_estimate"], 1e-15)
        self.assertEqual(out["reference_refused"], "")

    def test_double_keeps_the_uncertified_levels(self):
        out = self.converge(precision="double")
        self.assertEqual(out["reference_precision"], "double")
        self.assertEqual([lv["status"] for lv in out["levels"]].count("uncertified"), 3)
        self.assertFalse(any("quad" in note for note in out["notes"]))

    def test_the_cost_guard_keeps_the_double_reference(self):
        # A budget of 1 ms: the quad reference (seconds) is projected over it at its first check.
        out = self.converge(precision="auto", reference_budget=0.001)
        self.assertEqual(out["reference_precision"], "double")
        self.assertIn("over its budget of 0.001 s", out["reference_refused"])
        self.assertIn(out["reference_refused"], out["notes"][0])

    def test_work_precision_retries_too(self):
        # The same three NMB levels are the uncertified runs of the work-precision study.
        kwargs = dict(levels=8, solvers=["cvode"], tolerances=[1e-6], repeats=1, jobs=2)
        double = flexref.work_precision(self.scene, ["nmb"], precision="double", **kwargs)
        self.assertEqual([r["status"] for r in double["runs"]].count("uncertified"), 3)
        auto = flexref.work_precision(self.scene, ["nmb"], precision="auto", **kwargs)
        self.assertEqual(auto["reference_precision"], "quad")
        self.assertIn("could not certify 3 run(s): the study was repeated with a "
                      "quad-precision reference", auto["notes"][0])
        self.assertEqual([r["status"] for r in auto["runs"]], ["ok"] * 9)

    def test_an_unknown_precision_is_refused_with_the_list(self):
        with self.assertRaises(ValueError) as c:
            self.converge(precision="float")
        self.assertIn("expected auto, double, extended or quad", str(c.exception))


if __name__ == "__main__":
    unittest.main()
