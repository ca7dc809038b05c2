"""The foton Python module (issue 38): renders equal the command line's bit for bit with the
same seed, AOVs and sample counts arrive as NumPy arrays, bad input raises foton.InputError
with the command line's message, the progress callback sees every pass and can stop a render,
and compare() gives foton compare's figures.

Run by ctest (python_module) with PYTHONPATH at the built module and FOTON_BINARY and
FOTON_SOURCE_DIR set."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import foton

SOURCE = os.environ["FOTON_SOURCE_DIR"]
BINARY = os.environ["FOTON_BINARY"]
CORNELL = os.path.join(SOURCE, "scenes", "cornell-box.xml")


class ModuleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scene = foton.load_scene(CORNELL)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def test_render_equals_the_command_line_bit_for_bit(self):
        for integrator in ("path", "bdpt"):
            with self.subTest(integrator=integrator):
                out = self.path(integrator + ".exr")
                subprocess.run([BINARY, "render", CORNELL, "--integrator", integrator,
                                "--spp", "3", "--width", "40", "--height", "30", "--seed",
                                "7", "--threads", "2", "--aov", "albedo,depth", "-q", "-o", out],
                               check=True)
                r = self.scene.render(integrator=integrator, spp=3, width=40, height=30,
                                      seed=7, threads=2, aov=["albedo", "depth"])
                self.assertEqual(r.image.shape, (30, 40, 3))
                self.assertEqual(r.image.dtype, np.float32)
                self.assertTrue(np.array_equal(r.image, foton.read_exr(out)))
                albedo = foton.read_exr(out, ["Albedo.R", "Albedo.G", "Albedo.B"])
                self.assertTrue(np.array_equal(r.aovs["albedo"], albedo))
                self.assertTrue(np.array_equal(r.aovs["depth"], foton.read_exr(out, ["Z"])))
                self.assertEqual(r.spp, 3.0)
                self.assertTrue((r.samples == 3).all())
                # The EXR it writes is the command line's (pixels and channels).
                again = self.path(integrator + "-py.exr")
                r.write_exr(again)
                self.assertTrue(np.array_equal(foton.read_exr(again), r.image))
                self.assertEqual(foton.compare(again, out)["rmse"], 0.0)

    def test_aovs_and_stats(self):
        r = self.scene.render(integrator="path", spp=2, width=16, height=12, aov="all")
        self.assertEqual(sorted(r.aovs), ["albedo", "depth", "normal", "position", "variance"])
        self.assertEqual(r.aovs["normal"].shape, (12, 16, 6))
        self.assertEqual(r.aovs["depth"].shape, (12, 16))
        self.assertTrue((r.aovs["variance"] >= 0).all())
        self.assertEqual(r.stats["camera_rays"], 16 * 12 * 2)
        self.assertEqual(r.attributes["foton:integrator"].split()[0], "path")
        self.assertEqual(r.passes, 1)

    def test_bad_input_raises_with_the_command_lines_message(self):
        cases = [
            (dict(spp="many"), "render(spp=)"),
            (dict(colour=3), "render(colour=): unknown setting 'colour'"),
            (dict(integrator="nope"), "unknown renderer type 'nope'"),
            (dict(integrator="vcm", aov="variance"), "variance AOV needs pixel samples"),
            (dict(width=0), "width"),
            (dict(time=-1), "render(time=)"),
        ]
        for kwargs, message in cases:
            with self.subTest(kwargs=kwargs):
                with self.assertRaises(foton.InputError) as caught:
                    self.scene.render(**kwargs)
                self.assertIn(message, str(caught.exception))
        self.assertTrue(issubclass(foton.InputError, ValueError))
        with self.assertRaises(foton.InputError) as caught:
            foton.load_scene(self.path("missing.xml"))
        self.assertIn("missing.xml", str(caught.exception))
        # A bad setting in the file: its file and line.
        bad = self.path("bad.xml")
        with open(CORNELL) as f:
            text = f.read()
        with open(bad, "w") as f:
            f.write(text.replace("<renderer ", "<renderer spp_typo=\"3\" ", 1))
        line = next(i + 1 for i, l in enumerate(text.splitlines()) if "<renderer " in l)
        with self.assertRaises(foton.InputError) as caught:
            foton.load_scene(bad).render(spp=1, width=8, height=8)
        self.assertIn("bad.xml:%d" % line, str(caught.exception))
        with self.assertRaises(foton.InputError):
            foton.compare(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))
        with self.assertRaises(ValueError):
            foton.compare(np.zeros((4, 4)), np.zeros((4, 4, 3)))

    def test_progress_sees_every_pass_and_can_stop(self):
        seen = []
        r = self.scene.render(integrator="path", passes=4, width=16, height=16,
                              progress=lambda image, report: seen.append(
                                  (image.shape, report["passes"], report["last"])))
        self.assertEqual([s[1] for s in seen], [1, 2, 3, 4])
        self.assertEqual(seen[0][0], (16, 16, 3))
        self.assertTrue(seen[-1][2])
        self.assertEqual(r.passes, 4)

        def stop(image, report):
            if report["passes"] == 2:
                raise RuntimeError("enough")
        with self.assertRaises(RuntimeError):
            self.scene.render(integrator="path", passes=1000, width=16, height=16,
                              progress=stop)

    def test_compare(self):
        a = self.scene.render(integrator="path", spp=1, width=24, height=24, seed=1)
        b = self.scene.render(integrator="path", spp=1, width=24, height=24, seed=2)
        same = foton.compare(a, a.image)
        self.assertEqual(same["rmse"], 0.0)
        self.assertEqual(same["ssim"], 1.0)
        d = foton.compare(a, b)
        expected = np.sqrt(np.mean((a.image.astype(np.float64) - b.image) ** 2))
        self.assertAlmostEqual(d["rmse"], expected, places=6)
        self.assertLess(d["ssim"], 1.0)
        # A reference at twice the size is box-filtered down, as --reference's.
        big = np.repeat(np.repeat(b.image, 2, axis=0), 2, axis=1)
        self.assertAlmostEqual(foton.compare(a, big)["rmse"], d["rmse"], places=6)


    def test_the_readme_example_runs(self):
        with open(os.path.join(SOURCE, "README.md")) as f:
            readme = f.read()
        start = readme.index("```python\n") + len("```python\n")
        block = readme[start:readme.index("```", start)]
        run = subprocess.run([sys.executable, "-c", block], cwd=SOURCE, capture_output=True,
                             text=True, env=dict(os.environ))
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("(128, 128, 3)", run.stdout)
        self.assertIn("'rmse'", run.stdout)


if __name__ == "__main__":
    unittest.main()
