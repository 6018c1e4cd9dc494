#!/usr/bin/env python3
"""How close Caustic's error estimate without a reference comes to the true error.

For each scene, `caustic converge --points-per-doubling 1` renders to --spp and reports at
1, 2, 4, ... spp both the relMSE against the reference and the relMSE the render estimates
from its own samples (`estimated_relmse`: the later samples' mean against the earlier ones').
The true error is the measured relMSE less the reference's own noise (as suite.py subtracts
it); the table prints estimated / true at the chosen sample counts. Issue 30 asks for a factor
within 1.3 at 16, 64 and 256 spp on every reference and suite scene.

    python3 scripts/anchors/estimate_check.py [--spp 256] [--at 16,64,256] [--scenes a,b]
        [--caustic target/release/caustic] [--json out.json]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

from common import ROOT, SHARED, import_mitsuba, read_exr, relmse
import suite as suite_module


def scenes():
    """name -> (Caustic scene argument, extra arguments, reference folder, reference file)."""
    refs = os.path.join(SHARED, "references")
    out = {name: (scene, extra, folder, os.path.join(folder, "reference.exr"))
           for name, (scene, extra, _xml, folder, _generated) in suite_module.suite().items()}
    furnace = os.path.join(refs, "furnace")
    out["furnace"] = (os.path.join(furnace, "scene.gltf"), ["--environment", "1"], furnace, os.path.join(furnace, "analytic.exr"))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--at", default="16,64,256", help="sample counts to report")
    parser.add_argument("--scenes", default="cornell,furnace,cornell_dragon,env_mesh,million")
    parser.add_argument("--caustic", default=os.path.join(ROOT, "target", "release", "caustic"))
    parser.add_argument("--target", type=float, help="also render each scene with --target-error TARGET and "
                        "report its true relMSE (issue 30: 0.7 to 1.3 times the target for 1e-3)")
    parser.add_argument("--target-scenes", default="cornell,furnace,env_mesh", help="scenes for --target")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    at = [int(n) for n in args.at.split(",")]
    mi, why = import_mitsuba()
    if mi is None:
        print(f"{why}: the references cannot be read, so the reference noise and --target are skipped", file=sys.stderr)
    known = scenes()
    rows = []
    for name in args.scenes.split(","):
        if name not in known:
            sys.exit(f"unknown scene {name}; known: {', '.join(sorted(known))}")
        scene, extra, folder, reference = known[name]
        if not os.path.exists(reference):
            print(f"{name}: no reference at {reference}; skipped", file=sys.stderr)
            continue
        noise, source = suite_module.noise_floor(mi, folder, read_exr(mi, reference) if mi else None)
        with tempfile.TemporaryDirectory() as tmp:
            command = [args.caustic, "converge", scene, "--reference", reference, "--spp", str(args.spp),
                       "--points-per-doubling", "1", "--csv", os.path.join(tmp, "c.csv"), "--json"] + extra
            out = subprocess.run(command, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"{' '.join(command)} failed: {out.stderr.strip()[-2000:]}")
        points = {p["spp"]: p for p in json.loads(out.stdout)["points"]}
        for n in at:
            point = points.get(n)
            if point is None or point.get("estimated_relmse") is None:
                continue
            true = point["relmse"] - noise
            estimate = point["estimated_relmse"]
            rows.append({"scene": name, "spp": n, "relmse": point["relmse"], "noise": noise, "true": true,
                         "estimated": estimate, "ratio": estimate / true if true > 0 else None})
            print(f"{name} {n} spp: relMSE {point['relmse']:.3e} less reference noise {noise:.1e} ({source}) = "
                  f"{true:.3e}; estimated {estimate:.3e}; ratio {estimate / true:.3f}", file=sys.stderr)
    print("| scene | spp | true relMSE | estimated | estimated / true |")
    print("|---|---|---|---|---|")
    for r in rows:
        ratio = "-" if r["ratio"] is None else f"{r['ratio']:.2f}"
        print(f"| `{r['scene']}` | {r['spp']} | {r['true']:.2e} | {r['estimated']:.2e} | {ratio} |")
    targets = []
    if args.target is not None and mi is not None:
        for name in args.target_scenes.split(","):
            scene, extra, folder, reference = known[name]
            noise, _ = suite_module.noise_floor(mi, folder, read_exr(mi, reference))
            with tempfile.TemporaryDirectory() as tmp:
                image = os.path.join(tmp, "t.hdr")
                command = [args.caustic, "render", scene, "--target-error", str(args.target), "--size", "512x512",
                           "-o", image, "--json"] + extra
                out = subprocess.run(command, capture_output=True, text=True)
                if out.returncode != 0:
                    sys.exit(f"{' '.join(command)} failed: {out.stderr.strip()[-2000:]}")
                report = json.loads(out.stdout)
                true = relmse(read_exr(mi, image), read_exr(mi, reference)) - noise
            targets.append({"scene": name, "spp": report["spp"], "estimated": report["estimated_relmse"],
                            "true": true, "stopped_by": report["stopped_by"], "seconds": report["seconds"]})
        print(f"\n--target-error {args.target:g}:\n")
        print("| scene | spp | stopped by | estimated | true relMSE | true / target |")
        print("|---|---|---|---|---|---|")
        for t in targets:
            print(f"| `{t['scene']}` | {t['spp']} | {t['stopped_by']} | {t['estimated']:.2e} | {t['true']:.2e} | "
                  f"{t['true'] / args.target:.2f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"estimates": rows, "targets": targets}, f, indent=1)


if __name__ == "__main__":
    main()
