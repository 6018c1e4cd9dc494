#!/usr/bin/env python3
"""Build issue 31's stress scene: 10,000 instances of the 100k-triangle Stanford dragon
(1,000,000,000 instanced triangles) on a ground disk, for an environment map to light.

    python3 scripts/stress/make_dragons.py [--out target/stress/dragons] [--count 10000]
    caustic render target/stress/dragons/scene.gltf \
        --environment ../shared/assets/envmaps/venice_sunset_1k.hdr --spp 16 --json

The dragons stand on a square grid (1.6 dragon heights apart) with seeded random turns about
+Y and scales from 0.8 to 1.2, in four Lambert colours; the glTF gives each colour its own mesh
over the same accessors, which Caustic keeps as one prototype placed by instances (the Mitsuba
XML beside it, written by the same code as the suite's scenes, would load a billion triangles).
The files are generated, not committed (target/ is git-ignored).
"""

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "anchors"))
import make_suite  # noqa: E402  (the suite's readers and glTF writer)

COLOURS = {"jade": (0.25, 0.55, 0.35), "clay": (0.7, 0.35, 0.2), "bone": (0.8, 0.78, 0.7), "slate": (0.3, 0.33, 0.4)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join(make_suite.ROOT, "target", "stress", "dragons"))
    parser.add_argument("--count", type=int, default=10_000, help="dragons (a square grid holds them)")
    parser.add_argument("--seed", type=int, default=31)
    args = parser.parse_args()
    if args.count < 1:
        sys.exit("--count must be at least 1")
    vertices, faces = make_suite.read_ply(os.path.join(make_suite.MESHES, "stanford-dragon-100k.ply"))
    dragon = make_suite.stand(vertices, height=1.0)
    side = math.ceil(math.sqrt(args.count))
    spacing = 1.6
    extent = side * spacing
    rng = np.random.default_rng(args.seed)
    names = list(COLOURS)
    instances = []
    for i in range(args.count):
        x, z = (i % side) * spacing, (i // side) * spacing
        m = make_suite.yaw_translate(rng.uniform(0, 360), (x, 0.0, z))
        m[:3, :3] *= rng.uniform(0.8, 1.2)
        instances.append((f"dragon_{i}", "dragon", names[i % len(names)], m))
    ground = make_suite.disk(extent)
    instances.append(("ground", "ground", "ground", make_suite.yaw_translate(0, (extent / 2, 0.0, extent / 2))))
    materials = [make_suite.lambert(name, rgb) for name, rgb in COLOURS.items()] + [make_suite.lambert("ground", (0.5, 0.5, 0.5))]
    camera = ((-6.0, 9.0, -6.0), (extent * 0.45, 0.0, extent * 0.45), (0.0, 1.0, 0.0), 45.0)
    environment = make_suite.ENVMAP
    description = f"{args.count:,} instances of the 100k Stanford dragon on a ground disk, lit by venice_sunset_1k.hdr"
    make_suite.write_scene(args.out, "dragons", description, {"dragon": (dragon, faces), "ground": ground}, instances, materials, camera,
                           environment)


if __name__ == "__main__":
    main()
