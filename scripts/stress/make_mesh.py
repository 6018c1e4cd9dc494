#!/usr/bin/env python3
"""Build issue 31's large single mesh: copies of the 100k-triangle Stanford dragon, each turned
and scaled at random and placed on a square grid, merged into ONE binary PLY (the default, 100
copies, is 10,000,000 triangles), for the build-time comparison with Embree:

    python3 scripts/stress/make_mesh.py [--out target/stress/mesh10m.ply] [--copies 100]
    caustic bench target/stress/mesh10m.ply --json              # bvh_build_ms
    embree_native target/stress/mesh10m.ply RAYS.bin            # build_ms (../shared/anchors)

The copies overlap their neighbours' bounds (1.0 dragon heights apart, scales 0.8 to 1.2), so
the builder sees one dense mesh, not separable clusters. The file is generated, not committed.
"""

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "anchors"))
import make_suite  # noqa: E402  (the suite's PLY reader and writer)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join(make_suite.ROOT, "target", "stress", "mesh10m.ply"))
    parser.add_argument("--copies", type=int, default=100)
    parser.add_argument("--seed", type=int, default=31)
    args = parser.parse_args()
    if args.copies < 1:
        sys.exit("--copies must be at least 1")
    vertices, faces = make_suite.read_ply(os.path.join(make_suite.MESHES, "stanford-dragon-100k.ply"))
    dragon = make_suite.stand(vertices, height=1.0)
    side = math.ceil(math.sqrt(args.copies))
    rng = np.random.default_rng(args.seed)
    all_vertices, all_faces = [], []
    for i in range(args.copies):
        m = make_suite.yaw_translate(rng.uniform(0, 360), ((i % side) * 1.0, 0.0, (i // side) * 1.0))
        m[:3, :3] *= rng.uniform(0.8, 1.2)
        all_vertices.append(dragon @ m[:3, :3].T + m[:3, 3])
        all_faces.append(faces + i * len(dragon))
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    make_suite.write_ply(args.out, np.concatenate(all_vertices).astype(np.float32), np.concatenate(all_faces))
    print(f"{args.out}: {sum(len(f) for f in all_faces):,} triangles")


if __name__ == "__main__":
    main()
