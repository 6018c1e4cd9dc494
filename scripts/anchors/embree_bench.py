#!/usr/bin/env python3
"""Embree anchor for `caustic bench`: BVH build time and closest-hit throughput of Embree
(the `embreex` package) and Caustic on the same meshes and the very same rays, in one run.

For each mesh it writes a primary ray set (a pinhole grid framing the mesh) and an incoherent
one (cosine bounces off the primary hits, found by Embree; misses restart at random points in
the bounds), traces both with Embree and with `caustic bench MESH --rays FILE --hits OUT`,
checks that the two tracers agree ray by ray, and prints the ratios.

    pip install embreex trimesh numpy
    python3 scripts/anchors/embree_bench.py [--caustic target/release/caustic] [--grid 1024] MESH...

Embree's `run` is a single-threaded loop over rays (embreex), so its throughput is also given
scaled to the machine's cores (`--embree-threads`, default: all of them) by running that many
processes on disjoint slices, which is how Embree would be used to compare with a device that
uses every core.
"""

import argparse
import json
import multiprocessing
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import trimesh
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh


def load_triangles(path):
    """The mesh's triangles in file face order, as (n, 3, 3) float32."""
    mesh = trimesh.load(path, force="mesh", process=False, maintain_order=True)
    return np.ascontiguousarray(mesh.vertices[mesh.faces], dtype=np.float32)


def build_scene(triangles):
    """An Embree scene holding the triangles, committed; returns it with the build seconds."""
    start = time.perf_counter()
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, triangles)
    # Embree commits (builds the BVH) lazily on the first query.
    scene.run(np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32), output=0)
    return scene, time.perf_counter() - start


def primary_rays(triangles, grid):
    """A grid x grid pinhole ray set, 45 degree field of view, framing the mesh from +z."""
    lo, hi = triangles.reshape(-1, 3).min(0), triangles.reshape(-1, 3).max(0)
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
    eye = centre + np.array([0.3, 0.4, 1.0]) / np.linalg.norm([0.3, 0.4, 1.0]) * radius / np.tan(np.radians(22.5))
    forward = (centre - eye) / np.linalg.norm(centre - eye)
    right = np.cross(forward, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    s = (np.arange(grid) + 0.5) / grid * 2 - 1
    x, y = np.meshgrid(s, -s)
    half = np.tan(np.radians(22.5))
    d = forward + half * (x.reshape(-1, 1) * right + y.reshape(-1, 1) * up)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.broadcast_to(eye, d.shape)
    return np.ascontiguousarray(o, np.float32), np.ascontiguousarray(d, np.float32)


def incoherent_rays(scene, triangles, origins, directions, rng):
    """Cosine-distributed bounces off the primary hits; misses start anywhere in the bounds."""
    hit = scene.run(origins, directions, output=1)
    n = len(origins)
    lo, hi = triangles.reshape(-1, 3).min(0), triangles.reshape(-1, 3).max(0)
    normal = hit["Ng"] / np.maximum(np.linalg.norm(hit["Ng"], axis=1, keepdims=True), 1e-30)
    normal = np.where((np.sum(normal * directions, axis=1) > 0)[:, None], -normal, normal)
    u1, u2 = rng.random(n), rng.random(n)
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    local = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - u1)], axis=1)
    helper = np.where((np.abs(normal[:, 0]) > 0.9)[:, None], [0, 1, 0], [1, 0, 0])
    t = np.cross(helper, normal)
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-30)
    b = np.cross(normal, t)
    d = local[:, :1] * t + local[:, 1:2] * b + local[:, 2:] * normal
    p = origins + hit["tfar"][:, None] * directions + normal * (1e-4 * np.linalg.norm(hi - lo))
    missed = hit["primID"] < 0
    p[missed] = lo + rng.random((missed.sum(), 3)) * (hi - lo)
    z = 1 - 2 * rng.random(missed.sum())
    a = 2 * np.pi * rng.random(missed.sum())
    rz = np.sqrt(1 - z * z)
    d[missed] = np.stack([rz * np.cos(a), rz * np.sin(a), z], axis=1)
    return np.ascontiguousarray(p, np.float32), np.ascontiguousarray(d, np.float32)


def _trace_slice(args):
    path, origins, directions, repeats = args
    scene, _ = build_scene(load_triangles(path))
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        scene.run(origins, directions, output=0)
        best = min(best, time.perf_counter() - start)
    return best


def embree_throughput(path, scene, origins, directions, repeats, processes):
    """Best Mrays/s of one thread, and of `processes` threads tracing disjoint slices."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        scene.run(origins, directions, output=0)
        best = min(best, time.perf_counter() - start)
    single = len(origins) / best / 1e6
    if processes <= 1:
        return single, single
    slices = [(path, o, d, repeats) for o, d in zip(np.array_split(origins, processes), np.array_split(directions, processes))]
    with multiprocessing.Pool(processes) as pool:
        times = pool.map(_trace_slice, slices)
    return single, len(origins) / max(times) / 1e6


def caustic_trace(caustic, path, rays_file, hits_file, repeats, layout):
    """`caustic bench --rays` on the file: its JSON report, and its hits (t, triangle)."""
    out = subprocess.run(
        [caustic, "bench", path, "--rays", rays_file, "--hits", hits_file, "--repeats", str(repeats),
         "--bvh-layout", layout, "--json"],
        check=True, capture_output=True, text=True,
    )
    whole = json.loads(out.stdout)
    report = dict(whole["meshes"][0], adapter=f"{whole['adapter']}, {whole['driver']}")
    raw = np.fromfile(hits_file, dtype="<u4")
    n = len(raw) // 2
    return report, raw[:n].view("<f4"), raw[n:].view("<i4")


def agreement(scene, origins, directions, t, triangle):
    """Fraction of rays on which both tracers report the same triangle (or both miss), and the
    largest relative distance difference among those."""
    hit = scene.run(origins, directions, output=1)
    same = hit["primID"] == triangle
    both = same & (triangle >= 0)
    rel = np.abs(hit["tfar"][both] - t[both]) / np.maximum(hit["tfar"][both], 1e-30)
    return same.mean(), (rel.max() if rel.size else 0.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("--caustic", default="target/release/caustic")
    parser.add_argument("--grid", type=int, default=1024)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--embree-threads", type=int, default=os.cpu_count())
    parser.add_argument("--bvh-layout", default="wide", choices=["wide", "wide-exact", "binary"], help="Caustic's node layout")
    args = parser.parse_args()
    rng = np.random.default_rng(7)
    rows = []
    adapter = None
    with tempfile.TemporaryDirectory() as tmp:
        for path in args.meshes:
            triangles = load_triangles(path)
            scene, build_s = build_scene(triangles)
            o, d = primary_rays(triangles, args.grid)
            sets = {"primary": (o, d), "incoherent": incoherent_rays(scene, triangles, o, d, rng)}
            for kind, (origins, directions) in sets.items():
                rays_file, hits_file = os.path.join(tmp, kind + ".rays"), os.path.join(tmp, kind + ".hits")
                np.concatenate([origins, directions], axis=1).astype("<f4").tofile(rays_file)
                report, t, tri = caustic_trace(args.caustic, path, rays_file, hits_file, args.repeats, args.bvh_layout)
                adapter = report["adapter"]
                single, threaded = embree_throughput(path, scene, origins, directions, args.repeats, args.embree_threads)
                same, rel = agreement(scene, origins, directions, t, tri)
                rows.append((os.path.basename(path), len(triangles), kind, build_s * 1e3, report["bvh_build_ms"],
                             single, threaded, report["mrays_per_second"], same, rel))
    print(f"threads for Embree's throughput: 1 and {args.embree_threads}; rays: {args.grid}x{args.grid}; "
          f"Caustic's BVH layout: {args.bvh_layout}; Caustic's adapter: {adapter}")
    print("| mesh | triangles | rays | build ms Embree | build ms Caustic | ratio | Mrays/s Embree 1T | "
          f"Embree {args.embree_threads}T | Caustic | Caustic / Embree {args.embree_threads}T | same triangle | max rel t diff |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for m, n, kind, be, bc, e1, en, c, same, rel in rows:
        print(f"| {m} | {n} | {kind} | {be:.1f} | {bc:.1f} | {bc / be:.2f} | {e1:.2f} | {en:.2f} | {c:.2f} | "
              f"{c / en:.2f} | {same * 100:.2f}% | {rel:.1e} |")


if __name__ == "__main__":
    sys.exit(main())
