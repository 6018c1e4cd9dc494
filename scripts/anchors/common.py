"""Helpers shared by the Mitsuba anchors (mitsuba_converge.py, suite.py): the error metric,
the time to an error, the reference's own noise, and importing Mitsuba 3 with a usable LLVM.

Install Mitsuba 3 (its `llvm_ad_rgb` variant JIT-compiles with the system LLVM, and Dr.Jit
needs LLVM >= 16: Debian 12's default 14/15 crash it):

    pip install mitsuba numpy          # add --break-system-packages if pip refuses
    apt-get update && apt-get install -y libllvm19    # bookworm-backports; if apt cannot
    # find it: apt-get install -y -t bookworm-backports libllvm19
"""

import math
import os

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
RELMSE_EPSILON = 1e-2


def relmse(image, reference, epsilon=RELMSE_EPSILON):
    """Relative MSE over pixels and channels, as `caustic converge` computes it."""
    return float(np.mean((image - reference) ** 2 / (reference ** 2 + epsilon)))


def reference_noise(reference, stderr, epsilon=RELMSE_EPSILON):
    """The reference's own expected contribution to `relmse(image, reference)`: its per-pixel
    variance (stderr squared) over the same denominator. An independent render's relMSE
    against the reference is its own error plus this, so subtracting it leaves the render's."""
    return float(np.mean(stderr ** 2 / (reference ** 2 + epsilon)))


def time_to(points, target):
    """First time the error reaches `target`, interpolated in log-log; None if it never does."""
    for i, (seconds, error) in enumerate(points):
        if error <= target:
            if i == 0:
                return seconds
            (s0, e0), (s1, e1) = points[i - 1], points[i]
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(s0) + f * (math.log(s1) - math.log(s0)))
    return None


def import_mitsuba():
    """(mitsuba module with `llvm_ad_rgb` set, None) or (None, why it cannot be used)."""
    # Dr.Jit JIT-compiles with the system LLVM; point it at LLVM 19 when the default is too old.
    if os.path.exists(LIBLLVM):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", LIBLLVM)
    try:
        import mitsuba as mi
        mi.set_variant("llvm_ad_rgb")
    except Exception as error:  # ImportError, or a variant that cannot start (no LLVM)
        return None, f"Mitsuba 3 llvm_ad_rgb is not usable ({type(error).__name__}: {error})"
    return mi, None


def read_exr(mi, path):
    """The RGB channels of an EXR as a float32 array (through Mitsuba's Bitmap)."""
    return np.array(mi.Bitmap(path), np.float32)[..., :3]
