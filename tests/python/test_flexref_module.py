"""Tests of the Python module `flexref` (python/flexref_module.cpp), run by ctest with
PYTHONPATH=build/python from the repository root."""
import math
import os
import tempfile
import unittest

import numpy as np

import flexref


class ModuleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # free_spin shortened to 5 s: fast, with an exact solution.
        with open("scenes/free_spin.toml") as f:
            text = f.read().replace("end_time = 100.0", "end_time = 5.0")
        cls.dir = tempfile.TemporaryDirectory()
        cls.path = os.path.join(cls.dir.name, "fs5.toml")
        with open(cls.path, "w") as f:
            f.write(text)
        cls.scene = flexref.load_scene(cls.path)
        cls.ref = flexref.reference(cls.scene, rtol=1e-10)

    def test_scene_and_reference_columns(self):
        self.assertEqual(self.scene.name, "free_spin")
        self.assertEqual(self.scene.bodies, ["body"])
        self.assertEqual(len(self.scene.output_times), 51)
        self.assertEqual(self.ref.columns, self.scene.columns)
        e = np.array([self.ref[f"body.e{k}"] for k in range(4)])
        # The reference's Euler parameters are unit (the exact solution: to round-off).
        self.assertLess(np.max(np.abs(np.linalg.norm(e, axis=0) - 1.0)), 1e-12)
        # The estimate exists, is not 0 and is small (exact solution vs Odeint at 1e-13).
        self.assertGreater(self.ref.estimated_error, 0.0)
        self.assertLess(self.ref.estimated_error, 1e-9)
        self.assertEqual(self.ref.estimate["metric"], "relative")

    def test_compare_a_scheme_run_and_its_subset(self):
        run = flexref.run_scheme(self.scene, "c2", 1e-2)
        full = flexref.compare(run, self.ref)
        self.assertTrue(full.certified)
        # Only t, Euler parameters and W, every other output time: the rotation error at the
        # kept rows, measured by the same contract.
        d = run.to_dict()
        keep = {k: d[k][::2] for k in ["t"] + [f"body.e{k}" for k in range(4)]}
        sub = flexref.compare(keep, self.ref)
        self.assertEqual(sub.measured, ["body.rotation"])
        self.assertEqual(sub.rows, 26)
        rot = [q for q in full.quantities if q["name"] == "body.rotation"][0]
        # The default metric: the rotation's angle over pi rad, dimensionless.
        self.assertEqual(sub.unit, "1")
        self.assertEqual(sub.terms, "largest of body.rotation / pi rad")
        self.assertEqual(full.unit, "1")
        self.assertLessEqual(sub.value, rot["linf"] / math.pi)
        self.assertGreater(sub.value, 0.5 * rot["linf"] / math.pi)

    def test_errors_are_python_exceptions_with_flexrefs_messages(self):
        with self.assertRaises(flexref.InputError) as c:
            flexref.load_scene(os.path.join(self.dir.name, "missing.toml"))
        self.assertIn("missing.toml", str(c.exception))
        t = self.ref.times
        bad = {"t": t, "body.e0": np.ones_like(t), "body.e1": 0 * t, "body.e2": 0 * t,
               "body.e3": 0 * t}
        bad["body.e1"][7] = math.nan
        with self.assertRaises(flexref.InputError) as c:
            flexref.compare(bad, self.ref)
        self.assertIn("run:8: key 'body.e1': row 8: non-finite", str(c.exception))
        self.assertTrue(issubclass(flexref.InputError, ValueError))
        with self.assertRaises(ValueError):
            flexref.reference(self.scene, precision="quad")
        with self.assertRaises(ValueError):
            flexref.run_scheme(self.scene, "rk4", 1e-2)
        with self.assertRaises(flexref.InputError) as c:
            flexref.compare({"t": t, "plate.e0": t}, self.ref)
        self.assertIn("unknown body 'plate'", str(c.exception))

    def test_observed_order_of_the_built_in_schemes(self):
        runs = [(h, flexref.run_scheme(self.scene, "nmb", h)) for h in (0.02, 0.01, 0.005)]
        result = flexref.convergence(self.ref, runs, label="nmb", claimed_order=2)
        # NMB is second order (docs/schemes.md): a two-sided band of 0.1.
        self.assertAlmostEqual(result["observed_order"], 2.0, delta=0.1)
        self.assertEqual([lv["status"] for lv in result["levels"]], ["ok"] * 3)
        self.assertIn("nmb", [s[0] for s in flexref.schemes()])

    def test_genalpha_options_reach_the_stepper(self):
        # lie::MethodOptions from keyword arguments: the default rho_inf is 0.9, and 0.5 damps
        # differently, so the run and a converge study change with it.
        default = flexref.run_scheme(self.scene, "genalpha", 1e-2)
        mild = flexref.run_scheme(self.scene, "genalpha", 1e-2, rho_inf=0.9)
        damped = flexref.run_scheme(self.scene, "genalpha", 1e-2, rho_inf=0.5)
        perturbed = flexref.run_scheme(self.scene, "genalpha", 1e-2, perturbed_start=True)
        for column in ("body.e1", "body.W1"):
            np.testing.assert_array_equal(default[column], mild[column])
            self.assertFalse(np.array_equal(default[column], damped[column]))
            self.assertFalse(np.array_equal(default[column], perturbed[column]))
        errors = {}
        for rho in (0.5, 0.9):
            out = flexref.converge(self.scene, ["genalpha"], dt=0.02, levels=3,
                                   reference_solver="cvode", precision="double", jobs=1,
                                   rho_inf=rho)
            errors[rho] = [lv["error"] for lv in out["levels"]]
        self.assertEqual(len(errors[0.5]), 3)
        for a, b in zip(errors[0.5], errors[0.9]):
            self.assertNotEqual(a, b)

    def test_method_options_that_apply_to_no_scheme_are_refused(self):
        with self.assertRaisesRegex(ValueError, "rho_inf applies only to genalpha"):
            flexref.run_scheme(self.scene, "c2", 1e-2, rho_inf=0.5)
        with self.assertRaisesRegex(ValueError, "perturbed_start applies only to genalpha"):
            flexref.converge(self.scene, ["c1", "nmb"], perturbed_start=True)
        with self.assertRaisesRegex(ValueError, "rho_inf"):
            flexref.run_scheme(self.scene, "genalpha", 1e-2, rho_inf=1.5)
        with self.assertRaisesRegex(ValueError, "method option 'gain'"):
            flexref.run_scheme(self.scene, "c2", 1e-2, options={"gain": 1.0})
        with self.assertRaisesRegex(ValueError, "method option 'gain'"):
            flexref.work_precision(self.scene, ["nmb"], options={"gain": 1.0})


if __name__ == "__main__":
    unittest.main()
