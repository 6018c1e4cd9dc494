#!/usr/bin/env python3
"""Embree anchor for BVH build time on large meshes: Embree (the `embreex` package) and
`caustic bench` build a BVH over the very same triangles, in one run.

The mesh is the Stanford dragon (100k triangles) subdivided 1-to-4 at edge midpoints until it
has at least `--triangles` triangles (two rounds: 1.6M), written as a binary PLY that both
tracers load; any other mesh file can be given instead. Embree's time is the scene creation,
the copy of the triangles into it and the build (the first query commits the scene), best of
`--repeats`; Caustic's is `bvh_build_ms` of `caustic bench MESH --json` (binned SAH, parallel
above 4,096 triangles), best of as many runs.

    pip install embreex trimesh numpy
    python3 scripts/anchors/embree_build.py [--caustic target/release/caustic] [--triangles 1000000] [MESH]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import trimesh

from embree_bench import build_scene, load_triangles


def subdivided(path, at_least):
    """The mesh at `path` subdivided 1-to-4 until it has at least `at_least` triangles."""
    mesh = trimesh.load(path, force="mesh", process=False, maintain_order=True)
    while len(mesh.faces) < at_least:
        mesh = mesh.subdivide()
    return mesh


def caustic_build_ms(caustic, path):
    """Caustic's BVH build milliseconds for the mesh (`caustic bench --json`)."""
    out = subprocess.run(
        [caustic, "bench", path, "--grid", "16", "--repeats", "1", "--json"],
        check=True, capture_output=True, text=True,
    )
    report = json.loads(out.stdout)["meshes"][0]
    return report["bvh_build_ms"], report["triangles"], report["bvh_sah_cost"]


def main():
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh", nargs="?", help="a mesh file to build as it is (default: the subdivided dragon)")
    parser.add_argument("--caustic", default=os.path.join(root, "target/release/caustic"))
    parser.add_argument("--dragon", default=os.path.join(root, "../shared/assets/meshes/stanford-dragon-100k.ply"))
    parser.add_argument("--triangles", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = args.mesh
        if path is None:
            path = os.path.join(tmp, "dragon-subdivided.ply")
            subdivided(args.dragon, args.triangles).export(path)
        triangles = load_triangles(path)
        embree_ms = min(build_scene(triangles)[1] for _ in range(args.repeats)) * 1e3
        runs = [caustic_build_ms(args.caustic, path) for _ in range(args.repeats)]
        caustic_ms = min(r[0] for r in runs)
        name = os.path.basename(args.mesh) if args.mesh else f"dragon subdivided ({os.path.basename(args.dragon)})"
    print(f"| mesh | triangles | build ms Embree | build ms Caustic | Caustic / Embree | Caustic SAH cost |")
    print("|---|---|---|---|---|---|")
    print(f"| {name} | {len(triangles)} (Caustic: {runs[0][1]}) | {embree_ms:.1f} | {caustic_ms:.1f} | "
          f"{caustic_ms / embree_ms:.2f} | {runs[0][2]:.2f} |")


if __name__ == "__main__":
    sys.exit(main())
