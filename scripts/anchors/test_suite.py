#!/usr/bin/env python3
"""Checks of the suite runner's arithmetic and of make_suite.py's two scene forms, without
rendering (seconds; no Mitsuba, no GPU, no ../shared needed):

    python3 scripts/anchors/test_suite.py
"""

import contextlib
import io
import json
import os
import re
import stat
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import make_suite  # noqa: E402
import suite  # noqa: E402


class Metrics(unittest.TestCase):
    def test_reference_noise_subtracted_leaves_the_renders_own_error(self):
        rng = np.random.default_rng(1)
        truth = rng.uniform(0.05, 2.0, (256, 256, 3))
        ref_sigma, image_sigma = 0.03 * truth, 0.05 * truth
        reference = truth + rng.normal(0, 1, truth.shape) * ref_sigma
        image = truth + rng.normal(0, 1, truth.shape) * image_sigma
        own = common.relmse(image, truth)
        corrected = common.relmse(image, reference) - common.reference_noise(reference, ref_sigma)
        print(f"relMSE against the truth {own:.4e}, against the noisy reference minus its noise {corrected:.4e}")
        self.assertAlmostEqual(corrected / own, 1.0, delta=0.03, msg="corrected relMSE within 3% of the true one")

    def test_time_to_target_follows_the_inverse_spp_law(self):
        # 1 M paths/s, 512x512: 64 spp take 16.78 s; relMSE 4e-3 -> 256 spp -> 67.1 s.
        seconds = suite.time_to_target(1.0, 4e-3, 64, 512 * 512)
        self.assertAlmostEqual(seconds, 256 * 512 * 512 / 1e6, places=6, msg=f"{seconds} s")
        self.assertIsNone(suite.time_to_target(1.0, None, 64, 512 * 512))


class SceneForms(unittest.TestCase):
    def test_time_on_the_curve_interpolates_the_crossing_or_extrapolates_its_slope(self):
        pixels = 100
        # rate 1e-4 M paths/s: the first pass of 1 spp over 100 pixels takes 1 s.
        points = [{"spp": 1, "seconds": 5.0, "relmse": 4e-3}, {"spp": 2, "seconds": 6.0, "relmse": 2e-3},
                  {"spp": 4, "seconds": 8.0, "relmse": 5e-4}]
        # Times 1, 2, 4 s; relMSE 2e-3 at 2 s and 5e-4 at 4 s: slope -2, so 1e-3 at 2 sqrt(2) s.
        self.assertAlmostEqual(suite.time_on_curve(points, 0.0, 1e-4, pixels), 2 * 2 ** 0.5, places=9)
        # Still above the target: along the last two points' slope (relMSE 4e-3 -> 2e-3 from
        # 1 to 2 s, slope -1), 1e-3 at 4 s.
        self.assertAlmostEqual(suite.time_on_curve(points[:2], 0.0, 1e-4, pixels), 4.0, places=9)
        # A curve that does not fall has no time.
        flat = [{"spp": 1, "seconds": 0.0, "relmse": 4e-3}, {"spp": 2, "seconds": 1.0, "relmse": 4e-3}]
        self.assertIsNone(suite.time_on_curve(flat, 0.0, 1e-4, pixels))

    def test_ply_round_trip(self):
        rng = np.random.default_rng(2)
        vertices = rng.normal(size=(50, 3)).astype(np.float32)
        faces = rng.integers(0, 50, (80, 3)).astype(np.uint32)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "m.ply")
            make_suite.write_ply(path, vertices, faces)
            v, f = make_suite.read_ply(path)
        np.testing.assert_array_equal(v, vertices)
        np.testing.assert_array_equal(f, faces)

    def test_gltf_and_xml_place_the_same_triangles(self):
        vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0.5]], np.float32)
        faces = np.array([[0, 1, 2]], np.uint32)
        matrix = make_suite.yaw_translate(30, [5, 1, -2])
        materials = [make_suite.lambert("grey", [0.5, 0.5, 0.5]), {"name": "glass", "kind": "glass"},
                     {"name": "metal", "kind": "metal", "roughness": 0.3}]
        instances = [("a", "tri", "grey", matrix), ("b", "tri", "metal", np.eye(4))]
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stderr(io.StringIO()):
            make_suite.write_scene(tmp, "t", "test", {"tri": (vertices, faces)}, instances, materials,
                                   ([0, 1, 5], [0, 1, 0], [0, 1, 0], 40.0))
            with open(os.path.join(tmp, "scene.gltf")) as f:
                gltf = json.load(f)
            with open(os.path.join(tmp, "scene.bin"), "rb") as f:
                blob = f.read()
            with open(os.path.join(tmp, "scene.xml")) as f:
                xml = f.read()
            ply_vertices, _ = make_suite.read_ply(os.path.join(tmp, "meshes", "tri.ply"))
        node = gltf["nodes"][0]
        accessor = gltf["accessors"][gltf["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
        view = gltf["bufferViews"][accessor["bufferView"]]
        positions = np.frombuffer(blob, "<f4", accessor["count"] * 3, view["byteOffset"]).reshape(-1, 3)
        gltf_matrix = np.array(node["matrix"]).reshape(4, 4).T  # column-major
        xml_matrix = np.array([float(x) for x in re.search(r'<matrix value="([^"]+)"', xml).group(1).split()]).reshape(4, 4)
        place = lambda m, p: (np.c_[p, np.ones(len(p))] @ m.T)[:, :3]
        difference = np.abs(place(gltf_matrix, positions) - place(xml_matrix, ply_vertices)).max()
        print(f"glTF and XML world positions differ by {difference:.2e} at most")
        self.assertLess(difference, 1e-6, "the two forms place the triangle at the same world positions")
        self.assertIn('type="roughconductor"', xml)
        self.assertIn('name="alpha" value="0.09"', xml, "roughness 0.3 is alpha 0.09 in Mitsuba")
        metal = gltf["materials"][2]["pbrMetallicRoughness"]
        self.assertEqual((metal["metallicFactor"], metal["roughnessFactor"], metal["baseColorFactor"][:3]), (1.0, 0.3, [1.0] * 3))


class Runner(unittest.TestCase):
    def test_without_mitsuba_it_says_so_and_measures_caustic_alone(self):
        with tempfile.TemporaryDirectory() as tmp:
            fake = os.path.join(tmp, "caustic")
            points = [{"spp": s, "seconds": s * 0.5, "relmse": 0.2 / s} for s in (1, 2, 4, 8)]
            with open(fake, "w") as f:
                f.write("#!/bin/sh\necho '" + json.dumps({"width": 512, "height": 512, "points": points}) + "'\n")
            os.chmod(fake, os.stat(fake).st_mode | stat.S_IEXEC)
            open(os.path.join(tmp, "reference.exr"), "w").close()
            with open(os.path.join(tmp, "reference.json"), "w") as f:
                json.dump({"noise_floor_relmse": 0.001}, f)
            scenes = {"box": ("cornell", [], os.path.join(tmp, "missing.xml"), tmp, False)}
            saved = (suite.suite, suite.import_mitsuba, sys.argv)
            suite.suite = lambda: scenes
            suite.import_mitsuba = lambda: (None, "Mitsuba 3 llvm_ad_rgb is not usable (test)")
            sys.argv = ["suite.py", "--spp", "8", "--caustic", fake, "--json", os.path.join(tmp, "out.json")]
            err, out = io.StringIO(), io.StringIO()
            try:
                with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
                    suite.main()
            finally:
                suite.suite, suite.import_mitsuba, sys.argv = saved
            with open(os.path.join(tmp, "out.json")) as f:
                result = json.load(f)
        print(err.getvalue() + out.getvalue())
        self.assertIn("not usable (test); measuring Caustic alone", err.getvalue())
        row = result["scenes"][0]
        # 512x512 x 7 spp over 3.5 s; relMSE 0.025 minus the reference's 0.001.
        self.assertAlmostEqual(row["caustic"]["mpaths_per_s"], 512 * 512 * 7 / 3.5 / 1e6, places=9)
        self.assertAlmostEqual(row["caustic"]["relmse"], 0.024, places=9)
        self.assertIsNone(row["mitsuba"])
        self.assertIsNone(row["ratio"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
