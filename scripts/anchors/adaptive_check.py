#!/usr/bin/env python3
"""Adaptive against uniform sampling at the same target error (issue 30, item 3).

For each scene, `caustic render --target-error E` runs with `--adaptive true` and with
`--adaptive false`, alternately (--rounds times each: identical runs on these machines spread
by 1.5x), and the table reports for each the mean samples per pixel, the seconds, the
estimated relMSE, the true relMSE against the reference (less the reference's own noise) and
the ratio uniform / adaptive of the median seconds, of the time to the same true error
(the uniform render's seconds scaled by its true relMSE over the adaptive one's, the 1/n law)
and of the true error per sample (true relMSE x mean spp: the error constant, which adaptive
sampling should lower).

    python3 scripts/anchors/adaptive_check.py [--target 2e-3] [--scenes a,b] [--rounds 1]
        [--caustic target/release/caustic] [--json out.json]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

from common import ROOT, import_mitsuba, read_exr, relmse
import suite as suite_module


def render(caustic, scene, extra, target, adaptive, reference, mi, noise):
    with tempfile.TemporaryDirectory() as tmp:
        image = os.path.join(tmp, "a.exr")
        command = [caustic, "render", scene, "--size", "512x512", "--target-error", str(target),
                   "--adaptive", "true" if adaptive else "false", "-o", image, "--json"] + extra
        out = subprocess.run(command, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"{' '.join(command)} failed: {out.stderr.strip()[-2000:]}")
        report = json.loads(out.stdout)
        true = relmse(read_exr(mi, image)[:, :, :3], reference) - noise
    spp = report["adaptive"]["spp_mean"] if report.get("adaptive") else report["spp"]
    return {"spp": spp, "seconds": report["seconds"], "estimated": report["estimated_relmse"], "true": true,
            "stopped_by": report["stopped_by"], "adaptive": report.get("adaptive")}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--target", type=float, default=2e-3)
    parser.add_argument("--scenes", default="cornell,cornell_dragon,env_mesh,million")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--caustic", default=os.path.join(ROOT, "target", "release", "caustic"))
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    mi, why = import_mitsuba()
    if mi is None:
        sys.exit(f"{why}: the references cannot be read")
    known = suite_module.suite()
    rows = []
    for name in args.scenes.split(","):
        if name not in known:
            sys.exit(f"unknown scene {name}; known: {', '.join(sorted(known))}")
        scene, extra, _xml, folder, _generated = known[name]
        reference = read_exr(mi, os.path.join(folder, "reference.exr"))[:, :, :3]
        noise, _ = suite_module.noise_floor(mi, folder, reference)
        runs = {True: [], False: []}
        for _ in range(args.rounds):
            for adaptive in (True, False):
                run = render(args.caustic, scene, extra, args.target, adaptive, reference, mi, noise)
                runs[adaptive].append(run)
                print(f"{name} {'adaptive' if adaptive else 'uniform'}: {run['spp']:.1f} spp, {run['seconds']:.2f} s, "
                      f"estimated {run['estimated']:.3e}, true {run['true']:.3e}, stopped by {run['stopped_by']}",
                      file=sys.stderr)
        row = {"scene": name, "target": args.target}
        for adaptive, key in ((True, "adaptive"), (False, "uniform")):
            r = runs[adaptive]
            row[key] = {"spp": statistics.median(x["spp"] for x in r), "seconds": statistics.median(x["seconds"] for x in r),
                        "estimated": statistics.median(x["estimated"] for x in r), "true": statistics.median(x["true"] for x in r)}
        a, u = row["adaptive"], row["uniform"]
        row["time_ratio"] = u["seconds"] / a["seconds"]
        row["equal_error_time_ratio"] = u["seconds"] * (u["true"] / a["true"]) / a["seconds"]
        row["error_constant_ratio"] = (u["true"] * u["spp"]) / (a["true"] * a["spp"])
        rows.append(row)
    print(f"| scene | uniform spp / s / true relMSE | adaptive spp / s / true relMSE | time uniform / adaptive | "
          f"time to the same error, uniform / adaptive | error x spp uniform / adaptive |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        u, a = r["uniform"], r["adaptive"]
        print(f"| `{r['scene']}` | {u['spp']:.0f} / {u['seconds']:.1f} / {u['true']:.2e} | {a['spp']:.0f} / {a['seconds']:.1f} / "
              f"{a['true']:.2e} | {r['time_ratio']:.2f} | {r['equal_error_time_ratio']:.2f} | {r['error_constant_ratio']:.2f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
