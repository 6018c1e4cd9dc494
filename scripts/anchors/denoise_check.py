#!/usr/bin/env python3
"""The denoiser against more samples, in NVIDIA's FLIP (issue 30, item 5).

For each scene, `caustic render --size 512x512 --spp N --denoise -o X.exr` renders at each
sample count of --spp; the EXR holds the samples' mean (`R`, `G`, `B`) and the denoised image
(`denoised.R/G/B`), so one render gives both. Each image is measured against the scene's
reference by relMSE (as `caustic converge` computes it, the reference's own noise not taken
off) and by FLIP: NVIDIA's reference implementation (`pip install flip-evaluator`), HDR-FLIP
on the linear images (its exposure range and ACES tone mapper), and LDR-FLIP on both images
tone mapped by ACES at exposure 0 (what `caustic render -o X.png` shows). Issue 30's target:
denoised 16 spp at least as close to the reference in FLIP as undenoised 256 spp, on the
Cornell box and `cornell_dragon`.

With --oidn the renders also write the albedo and normal AOVs, and Intel's Open Image
Denoise (`pip install pyoidn`: its CPU device, the `RT` filter at high quality, HDR input,
the same albedo and normal guides Caustic's filter reads) denoises the same samples' mean,
measured the same way: the well-kept learned denoiser issue 30 asks the filter to be
compared with.

    python3 scripts/anchors/denoise_check.py [--scenes cornell,cornell_dragon] [--spp 16,64,256]
        [--oidn] [--caustic target/release/caustic] [--json out.json]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from common import ROOT, import_mitsuba, read_exr, relmse
import suite as suite_module


def aces(x):
    """Narkowicz's fit of the ACES filmic curve, as Caustic's display transform applies it."""
    return np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)


def srgb(x):
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(np.maximum(x, 0.0031308), 1 / 2.4) - 0.055)


def layers(mi, path, guides=False):
    """The layers of one `--denoise` EXR by name, each HxWx3 float32: `samples` (the samples'
    mean) and `denoised`, and with `guides` the `albedo` and `normal` AOVs too."""
    bitmap = mi.Bitmap(path)
    names = [field.name for field in bitmap.struct_()]
    data = np.array(bitmap, np.float32)

    def take(channels):
        missing = [c for c in channels if c not in names]
        if missing:
            sys.exit(f"{path} lacks the channels {', '.join(missing)} (it has {', '.join(names)})")
        return np.stack([data[..., names.index(c)] for c in channels], axis=-1)

    images = {"samples": take(["R", "G", "B"]), "denoised": take(["denoised.R", "denoised.G", "denoised.B"])}
    if guides:
        images.update(albedo=take(["albedo.R", "albedo.G", "albedo.B"]), normal=take(["N.X", "N.Y", "N.Z"]))
    return images


def open_image_denoise(beauty, albedo, normal):
    """Open Image Denoise's `RT` filter (high quality, HDR) on the samples' mean, guided by the
    render's albedo and normal AOVs."""
    import pyoidn

    def contiguous(image):
        return np.ascontiguousarray(np.nan_to_num(image).astype(np.float32))

    return np.asarray(pyoidn.denoise(contiguous(np.maximum(beauty, 0.0)), albedo=contiguous(np.clip(albedo, 0.0, 1.0)),
                                     normal=contiguous(normal), hdr=True, quality="high"), np.float32)


def measure(flip, image, reference):
    hdr = flip.evaluate(reference, np.maximum(image, 0.0), "HDR", applyMagma=False)[1]
    ldr = flip.evaluate(srgb(aces(reference)), srgb(aces(np.maximum(image, 0.0))), "LDR", applyMagma=False)[1]
    return {"relmse": relmse(image, reference), "hdr_flip": float(hdr), "ldr_flip": float(ldr)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", default="cornell,cornell_dragon")
    parser.add_argument("--spp", default="16,64,256")
    parser.add_argument("--caustic", default=os.path.join(ROOT, "target", "release", "caustic"))
    parser.add_argument("--oidn", action="store_true", help="also measure Open Image Denoise on the same samples")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    if args.oidn:
        try:
            import pyoidn  # noqa: F401
        except ImportError:
            sys.exit("Open Image Denoise's Python package is not installed: pip install pyoidn")
    try:
        import flip_evaluator as flip
    except ImportError:
        sys.exit("NVIDIA's FLIP is not installed: pip install flip-evaluator")
    mi, why = import_mitsuba()
    if mi is None:
        sys.exit(f"{why}: the references cannot be read")
    known = suite_module.suite()
    rows = []
    print(f"{'scene':16} {'spp':>5} {'image':9} {'relMSE':>10} {'HDR-FLIP':>9} {'LDR-FLIP':>9}")
    for name in args.scenes.split(","):
        if name not in known:
            sys.exit(f"unknown scene {name}; known: {', '.join(sorted(known))}")
        scene, extra, _xml, folder, _generated = known[name]
        reference = read_exr(mi, os.path.join(folder, "reference.exr"))
        for spp in (int(n) for n in args.spp.split(",")):
            with tempfile.TemporaryDirectory() as tmp:
                path = os.path.join(tmp, "a.exr")
                command = [args.caustic, "render", scene, "--size", "512x512", "--spp", str(spp),
                           "--denoise", "-o", path, "--json"] + extra
                if args.oidn:
                    command += ["--aovs", "albedo,normal"]
                out = subprocess.run(command, capture_output=True, text=True)
                if out.returncode != 0:
                    sys.exit(f"{' '.join(command)} failed: {out.stderr.strip()[-2000:]}")
                images = layers(mi, path, guides=args.oidn)
            kinds = [("samples", images["samples"]), ("denoised", images["denoised"])]
            if args.oidn:
                kinds.append(("oidn", open_image_denoise(images["samples"], images["albedo"], images["normal"])))
            for kind, image in kinds:
                row = {"scene": name, "spp": spp, "image": kind, **measure(flip, image, reference)}
                rows.append(row)
                print(f"{name:16} {spp:>5} {kind:9} {row['relmse']:>10.3e} {row['hdr_flip']:>9.4f} {row['ldr_flip']:>9.4f}",
                      flush=True)
    if args.json:
        with open(args.json, "w") as out:
            json.dump(rows, out, indent=1)


if __name__ == "__main__":
    main()
