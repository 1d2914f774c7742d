"""The Python module texsim (docs/python.md), one process for the whole suite.

Run by ctest as PythonModule.Suite:
    PYTHONPATH=build/python /usr/bin/python3 -m unittest discover -s testbench/python -v
"""
import os
import runpy
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

import texsim

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CUBE = os.path.join(ROOT, "scenes", "cube.toml")
SMALL = {"output.width": 64, "output.height": 48}
TEXSIM_BIN = os.environ.get("TEXSIM_BIN", "")

# A scene as text: one procedural plane, no files.
SCENE_TEXT = """
[output]
width = 48
height = 32
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 0.0, -4.0]
fov_y = 60.0
[textures.checker]
source = "procedural:checker?size=64&cells=8"
[materials.floor]
texture = "checker"
filter = { mode = "bilinear" }
[[planes]]
material = "floor"
origin = [-4.0, 0.0, -1.0]
edge_u = [8.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -12.0]
"""

# A wall that fills the view.
WALL_TEXT = (SCENE_TEXT.replace("look_at = [0.0, 0.0, -4.0]", "look_at = [0.0, 1.0, -4.0]")
             .replace("origin = [-4.0, 0.0, -1.0]", "origin = [-50.0, -50.0, -2.0]")
             .replace("edge_u = [8.0, 0.0, 0.0]", "edge_u = [100.0, 0.0, 0.0]")
             .replace("edge_v = [0.0, 0.0, -12.0]", "edge_v = [0.0, 100.0, 0.0]"))


class Run(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cube = texsim.run(CUBE, overrides=SMALL)

    def test_report_has_the_cli_report_content(self):
        r = self.cube.report
        self.assertEqual(r["mode"], "timing")
        self.assertGreater(r["cycles"], 0)
        self.assertEqual(r["image"]["width"], 64)
        self.assertEqual(r["image"]["height"], 48)
        self.assertGreater(r["accuracy"]["psnr_db"], 10)

    def test_images_are_canvas_sized_float_arrays(self):
        for a in (self.cube.image, self.cube.reference, self.cube.error):
            self.assertEqual(a.shape, (48, 64, 3))
            self.assertEqual(a.dtype, np.float32)
        np.testing.assert_array_equal(self.cube.error,
                                      np.abs(self.cube.image - self.cube.reference))
        self.assertGreater(float(self.cube.image.max()), 0.1)

    def test_whole_canvas_buffer_is_not_copied(self):
        # A wall filling the view: its buffer is the whole canvas and is handed over (numpy
        # does not own it, a capsule does). The cube's buffer is only the cube's extent.
        r = texsim.run(WALL_TEXT, functional=True)
        self.assertEqual(r.report["fragments"], 48 * 32)
        self.assertFalse(r.image.flags["OWNDATA"])
        self.assertIsNotNone(r.image.base)
        self.assertTrue(self.cube.image.flags["OWNDATA"])

    def test_matches_the_cli(self):
        if not TEXSIM_BIN:
            self.skipTest("TEXSIM_BIN not set")
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([TEXSIM_BIN, "run", CUBE, "--set", "output.width=64", "--set",
                            "output.height=48", "--out", out], check=True,
                           stdout=subprocess.DEVNULL)
            import json
            with open(os.path.join(out, "report.json")) as f:
                cli = json.load(f)
        self.assertEqual(cli["cycles"], self.cube.report["cycles"])
        self.assertEqual(cli["accuracy"], self.cube.report["accuracy"])
        self.assertEqual(cli["blocks"], self.cube.report["blocks"])

    def test_functional_has_no_clock(self):
        r = texsim.run(CUBE, overrides=SMALL, functional=True)
        self.assertEqual(r.report["mode"], "functional")
        self.assertEqual(r.report["cycles"], 0)
        np.testing.assert_allclose(r.image, self.cube.image, atol=1e-6)

    def test_overrides_from_a_list_of_set_strings(self):
        r = texsim.run(CUBE, overrides=["output.width=32", "output.height=24"], functional=True)
        self.assertEqual(r.image.shape, (24, 32, 3))

    def test_dict_values_are_inline_tables(self):
        nearest = {"mode": "nearest", "address": "clamp"}
        r = texsim.run(CUBE, overrides={**SMALL, "materials.crate.filter": nearest},
                       functional=True)
        self.assertEqual(r.image.shape, (48, 64, 3))
        self.assertFalse(np.array_equal(r.image, self.cube.image))

    def test_scene_as_toml_text(self):
        r = texsim.run(SCENE_TEXT, functional=True)
        self.assertEqual(r.image.shape, (32, 48, 3))
        self.assertGreater(r.report["fragments"], 0)

    def test_reference_none(self):
        r = texsim.run(CUBE, overrides=SMALL, functional=True, reference="none")
        self.assertIsNone(r.reference)
        self.assertIsNone(r.error)
        self.assertIsNone(r.report["accuracy"]["psnr_db"])

    def test_ledger(self):
        r = texsim.run(CUBE, overrides=SMALL, ledger=True)
        self.assertIsNotNone(r.ledger)
        self.assertEqual(r.ledger, r.report["ledger"])
        self.assertIsNone(self.cube.ledger)

    def test_out_keeps_the_files(self):
        with tempfile.TemporaryDirectory() as out:
            texsim.run(CUBE, overrides=SMALL, functional=True, out=out)
            for f in ("report.json", "report.md", "image.png"):
                self.assertTrue(os.path.isfile(os.path.join(out, f)), f)


class Errors(unittest.TestCase):
    def test_unknown_key_raises_input_error_with_location(self):
        with self.assertRaises(texsim.InputError) as c:
            texsim.run(CUBE, overrides={"output.widht": 3})
        self.assertIsInstance(c.exception, ValueError)
        self.assertIn("unknown key 'widht'", c.exception.message)
        self.assertEqual(c.exception.location, "--set output.widht")

    def test_error_in_the_file_names_it(self):
        with self.assertRaises(texsim.InputError) as c:
            texsim.run(os.path.join(ROOT, "scenes", "sweeps", "cache_fifo.toml"))
        self.assertRegex(c.exception.location, r"cache_fifo\.toml:\d+:\d+$")

    def test_text_error_names_line_and_column(self):
        with self.assertRaises(texsim.InputError) as c:
            texsim.run(SCENE_TEXT.replace("fov_y = 60.0", "fov_y = \"wide\""))
        self.assertRegex(c.exception.location, r"^<scene text>:\d+:\d+$")

    def test_missing_file(self):
        with self.assertRaises(texsim.InputError) as c:
            texsim.run("no/such/scene.toml")
        self.assertEqual(c.exception.location, "no/such/scene.toml")

    def test_same_message_as_the_cli(self):
        if not TEXSIM_BIN:
            self.skipTest("TEXSIM_BIN not set")
        with self.assertRaises(texsim.InputError) as c:
            texsim.run(CUBE, overrides=["output.width=-3"])
        cli = subprocess.run([TEXSIM_BIN, "run", CUBE, "--set", "output.width=-3", "--out",
                              tempfile.gettempdir()], capture_output=True, text=True)
        self.assertNotEqual(cli.returncode, 0)
        self.assertIn(c.exception.message, cli.stderr)

    def test_bad_reference(self):
        with self.assertRaises(texsim.InputError):
            texsim.run(CUBE, reference="peer")


class Sweep(unittest.TestCase):
    def test_results_in_the_order_of_the_sets(self):
        sets = [{"output.width": w, "output.height": 24} for w in (16, 32, 48)]
        results = texsim.sweep(CUBE, sets, functional=True, jobs=2)
        self.assertEqual([r.image.shape[1] for r in results], [16, 32, 48])
        one = texsim.run(CUBE, overrides=sets[1], functional=True)
        np.testing.assert_array_equal(results[1].image, one.image)

    def test_an_error_in_one_job_raises(self):
        with self.assertRaises(texsim.InputError):
            texsim.sweep(CUBE, [SMALL, {"output.width": -1}], functional=True)


class Gil(unittest.TestCase):
    def test_released_during_a_run(self):
        # Another Python thread keeps running while the simulation runs.
        ticks = [0]
        done = threading.Event()

        def count():
            while not done.is_set():
                ticks[0] += 1
                time.sleep(0.001)

        t = threading.Thread(target=count)
        t.start()
        start = time.monotonic()
        texsim.run(CUBE, overrides={"output.width": 160, "output.height": 120}, threads=1)
        elapsed = time.monotonic() - start
        done.set()
        t.join()
        # Held, the counter would advance only at the run's start and end.
        self.assertGreater(ticks[0], max(3, elapsed * 100), (ticks[0], elapsed))


class Traces(unittest.TestCase):
    TEXTURES = [{"id": 0, "name": "checker", "source": "procedural:checker?size=64&cells=8",
                 "width": 64, "height": 64, "storage": ""}]

    def records(self, n=10):
        a = np.zeros(n, dtype=texsim.fragment_dtype)
        a["x"] = np.arange(n)
        a["y"] = 3
        a["u"] = np.linspace(0, 1, n)
        a["v"] = 0.5
        a["dudx"] = 1 / 64
        a["dvdy"] = 1 / 64
        return a

    def test_round_trip_binary_and_csv(self):
        a = self.records()
        with tempfile.TemporaryDirectory() as d:
            for name in ("t.trc", "t.csv"):
                path = os.path.join(d, name)
                texsim.write_trace(path, a, self.TEXTURES)
                b, textures = texsim.read_trace(path, textures=True)
                self.assertEqual(b.dtype, texsim.fragment_dtype)
                np.testing.assert_array_equal(b, a)
                self.assertEqual(textures, self.TEXTURES)

    def test_sampler_table_round_trips(self):
        a = self.records()
        a["sampler"][3] = 2
        samplers = [{"name": "pcf", "mode": "bilinear", "address_u": "clamp",
                     "address_v": "clamp", "compare": "less_or_equal"},
                    {"name": "texel", "mode": "nearest", "address_u": "border",
                     "address_v": "clamp", "border": (0.0, 0.0, 0.0, 1.0), "unnormalized": True,
                     "max_lod": 0.0}]
        with tempfile.TemporaryDirectory() as d:
            for name in ("t.trc", "t.csv"):
                path = os.path.join(d, name)
                texsim.write_trace(path, a, self.TEXTURES, samplers)
                b, textures, back = texsim.read_trace(path, samplers=True)
                np.testing.assert_array_equal(b, a)
                self.assertEqual([s["name"] for s in back], ["pcf", "texel"])
                self.assertEqual(back[0]["compare"], "less_or_equal")
                self.assertEqual(back[0]["address_w"], "wrap")  # left out: the default
                self.assertEqual(back[1]["border"], (0.0, 0.0, 0.0, 1.0))
                self.assertTrue(back[1]["unnormalized"])
                self.assertEqual(back[1]["max_lod"], 0.0)
            with self.assertRaises(texsim.InputError):
                texsim.write_trace(os.path.join(d, "u.trc"), a, self.TEXTURES,
                                   [{"name": "x", "min_lod": 2.0, "max_lod": 1.0}])
            with self.assertRaises(ValueError):
                texsim.write_trace(os.path.join(d, "v.trc"), a, self.TEXTURES,
                                   [{"name": "x", "mode": "cubic"}])

    def test_fields_by_name_from_another_dtype(self):
        a = self.records(4)
        fields = ["frame", "prim", "x", "y", "tex", "u", "v", "dudx", "dvdx", "dudy", "dvdy"]
        small = np.zeros(4, dtype=[(f, a.dtype[f]) for f in reversed(fields)])
        for f in fields:
            small[f] = a[f]
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "t.trc")
            texsim.write_trace(path, small, self.TEXTURES)
            np.testing.assert_array_equal(texsim.read_trace(path), a)

    def test_shipped_sample(self):
        a = texsim.read_trace(os.path.join(ROOT, "traces", "samples", "basic.trc"))
        self.assertGreater(len(a), 0)
        self.assertFalse(a.flags["OWNDATA"])

    def test_bad_trace_raises_input_error(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.trc")
            with open(path, "wb") as f:
                f.write(b"TEXSIMTR" + b"\0" * 8)
            with self.assertRaises(texsim.InputError) as c:
                texsim.read_trace(path)
            self.assertTrue(c.exception.location.startswith(path))

    def test_nan_is_refused(self):
        a = self.records(2)
        a["u"][1] = np.nan
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(texsim.InputError):
                texsim.write_trace(os.path.join(d, "t.trc"), a, self.TEXTURES)


class ParetoExample(unittest.TestCase):
    def test_writes_the_plot(self):
        with tempfile.TemporaryDirectory() as d:
            png = os.path.join(d, "pareto.png")
            argv = sys.argv
            sys.argv = ["pareto_example.py", png, "--small"]
            try:
                with open(os.devnull, "w") as null:
                    stdout, sys.stdout = sys.stdout, null
                    try:
                        runpy.run_path(os.path.join(ROOT, "docs", "pareto_example.py"),
                                       run_name="__main__")
                    except SystemExit as e:
                        self.assertEqual(e.code, 0)
                    finally:
                        sys.stdout = stdout
            finally:
                sys.argv = argv
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    unittest.main()
