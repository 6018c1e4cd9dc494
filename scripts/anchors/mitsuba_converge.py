#!/usr/bin/env python3
"""Mitsuba 3 anchor for `caustic converge`: time to reach a relative MSE on the Cornell box,
Mitsuba 3 (`llvm_ad_rgb` on the CPU, the variant that made the reference) against Caustic,
in the same run on the same machine.

    pip install mitsuba && apt-get install libllvm19   # Dr.Jit needs LLVM >= 16 (common.py says more)
    python3 scripts/anchors/mitsuba_converge.py [--caustic target/release/caustic] [--target 1e-3]

Both render `../shared/references/cornell` (Mitsuba its `scene.xml`, Caustic the identical
built-in Cornell box) at 512x512 and are compared with `reference.exr` by relMSE (epsilon
1e-2). Mitsuba renders at doubling sample counts after a warm-up render that pays its JIT
compilation; Caustic runs `caustic converge`. The time to the target error is interpolated in
log-log between measurements, as `caustic converge` does.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from common import import_mitsuba, relmse, time_to

mi, why = import_mitsuba()
if mi is None:
    sys.exit(why)


def mitsuba_points(scene_xml, reference, max_spp):
    mi.set_variant("llvm_ad_rgb")
    scene = mi.load_file(scene_xml)
    mi.render(scene, spp=1)  # warm-up: JIT compilation
    points, spp = [], 4
    while spp <= max_spp:
        start = time.perf_counter()
        image = np.array(mi.render(scene, spp=spp, seed=spp))
        seconds = time.perf_counter() - start
        points.append((seconds, relmse(image[..., :3], reference)))
        print(f"mitsuba {spp:>6} spp {seconds:8.2f} s relMSE {points[-1][1]:.3e}", file=sys.stderr)
        spp *= 2
    return points


def caustic_points(caustic, reference_path, max_spp):
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run(
            [caustic, "converge", "--reference", reference_path, "--spp", str(max_spp),
             "--csv", os.path.join(tmp, "c.csv"), "--json"],
            check=True, capture_output=True, text=True,
        )
    return [(p["seconds"], p["relmse"]) for p in json.loads(out.stdout)["points"]]


def main():
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--caustic", default=os.path.join(root, "target/release/caustic"))
    parser.add_argument("--references", default=os.path.join(root, "../shared/references/cornell"))
    parser.add_argument("--target", type=float, default=1e-3)
    parser.add_argument("--mitsuba-spp", type=int, default=1024)
    parser.add_argument("--caustic-spp", type=int, default=512)
    args = parser.parse_args()
    reference_path = os.path.join(args.references, "reference.exr")
    mi.set_variant("llvm_ad_rgb")
    reference = np.array(mi.Bitmap(reference_path))[..., :3]
    mitsuba = mitsuba_points(os.path.join(args.references, "scene.xml"), reference, args.mitsuba_spp)
    caustic = caustic_points(args.caustic, reference_path, args.caustic_spp)
    tm, tc = time_to(mitsuba, args.target), time_to(caustic, args.target)
    show = lambda t: "not reached" if t is None else f"{t:.1f} s"
    print(f"time to relMSE {args.target:g} on the Cornell box at 512x512: "
          f"Mitsuba 3 llvm_ad_rgb {show(tm)}, Caustic {show(tc)}"
          + (f", ratio Caustic / Mitsuba {tc / tm:.2f}" if tm and tc else ""))


if __name__ == "__main__":
    sys.exit(main())
