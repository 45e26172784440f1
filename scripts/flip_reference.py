#!/usr/bin/env python3
"""Reference LDR-FLIP values from NVIDIA's official implementation, to validate src/metrics/flip.rs.

Setup (once):
    python3 -m venv /tmp/flip-venv && /tmp/flip-venv/bin/pip install flip-evaluator pillow

Usage:
    /tmp/flip-venv/bin/python scripts/flip_reference.py TEST REF [--json] [--pixels x,y ...]
    /tmp/flip-venv/bin/python scripts/flip_reference.py --make-fixtures tests/data

TEST and REF are PNG (8-bit sRGB) or EXR (linear RGB) files, as flip-evaluator's loader reads
them. The evaluation is the one wavetrace uses ("LDR-FLIP on tonemapped images"):

  * EXR (linear, possibly HDR): clamp to [0, 1] (exposure 0, no tone curve), then LDR-FLIP on
    those linear values (`inputsRGB=False`). This equals sRGB-encoding the clamped values and
    letting FLIP decode them again, without 8-bit rounding.
  * PNG (sRGB-encoded): LDR-FLIP with `inputsRGB=True`, i.e. FLIP decodes sRGB to linear itself.

Default viewing conditions: 0.7 m from a 0.7 m wide, 3840 px monitor, i.e. 67.02 pixels per
degree (flip-evaluator's default). The mean printed is flip-evaluator's own mean of the map.

--make-fixtures DIR writes the small deterministic PNG pairs used by tests/metrics.rs; the noise
comes from an integer hash (not NumPy's RNG), so the bytes do not depend on library versions.
"""
import argparse
import json
import sys

import numpy as np

FIXTURE_W, FIXTURE_H = 64, 48


def hash_unit(i: int) -> float:
    """A value in [0, 1) from a 32-bit integer hash (lowbias32 by Chris Wellons)."""
    x = i & 0xFFFFFFFF
    x ^= x >> 16
    x = (x * 0x7FEB352D) & 0xFFFFFFFF
    x ^= x >> 15
    x = (x * 0x846CA68B) & 0xFFFFFFFF
    x ^= x >> 16
    return x / 2**32


def gradient():
    """sRGB values: red rises left to right, green top to bottom, blue constant."""
    img = np.zeros((FIXTURE_H, FIXTURE_W, 3))
    for y in range(FIXTURE_H):
        for x in range(FIXTURE_W):
            img[y, x] = (x / (FIXTURE_W - 1), y / (FIXTURE_H - 1), 0.5)
    return img


def add_noise(img, amplitude, seed):
    """Adds triangular noise in [-amplitude, amplitude] per channel (sRGB units)."""
    out = img.copy()
    h, w, _ = img.shape
    for y in range(h):
        for x in range(w):
            for c in range(3):
                i = ((seed * h + y) * w + x) * 3 + c
                n = hash_unit(2 * i) + hash_unit(2 * i + 1) - 1.0
                out[y, x, c] += amplitude * n
    return out


def checkerboard(cell=8):
    """Light and dark grey squares, `cell` pixels wide."""
    img = np.zeros((FIXTURE_H, FIXTURE_W, 3))
    for y in range(FIXTURE_H):
        for x in range(FIXTURE_W):
            img[y, x] = 0.9 if ((x // cell) + (y // cell)) % 2 == 0 else 0.1
    return img


def box_blur(img, radius=1):
    """(2r+1)^2 box filter with clamp-to-edge borders."""
    h, w, _ = img.shape
    out = np.zeros_like(img)
    for y in range(h):
        for x in range(w):
            acc = np.zeros(3)
            for dy in range(-radius, radius + 1):
                for dx in range(-radius, radius + 1):
                    acc += img[min(max(y + dy, 0), h - 1), min(max(x + dx, 0), w - 1)]
            out[y, x] = acc / (2 * radius + 1) ** 2
    return out


def hue_ramp():
    """Saturated colours: hue varies along x, value along y."""
    img = np.zeros((FIXTURE_H, FIXTURE_W, 3))
    for y in range(FIXTURE_H):
        for x in range(FIXTURE_W):
            h = 6.0 * x / FIXTURE_W
            v = 0.35 + 0.6 * y / (FIXTURE_H - 1)
            k = np.array([5.0, 3.0, 1.0])
            rgb = v - v * 0.8 * np.clip(np.minimum((k + h) % 6, 4 - (k + h) % 6), 0, 1)
            img[y, x] = rgb
    return img


def colour_shift(img):
    """A white-balance error: scale R down, B up (sRGB units)."""
    return img * np.array([0.88, 1.0, 1.12])


def save_png(path, srgb):
    from PIL import Image

    q = np.clip(np.round(np.clip(srgb, 0.0, 1.0) * 255.0), 0, 255).astype(np.uint8)
    Image.fromarray(q, "RGB").save(path, optimize=True)


def make_fixtures(directory):
    import os

    os.makedirs(directory, exist_ok=True)
    g = gradient()
    c = checkerboard()
    h = hue_ramp()
    pairs = {
        "flip_gradient_ref.png": g,
        "flip_gradient_noise.png": add_noise(g, 0.08, seed=1),
        "flip_checker_ref.png": c,
        "flip_checker_blur.png": box_blur(c, 1),
        "flip_hue_ref.png": h,
        "flip_hue_shift.png": colour_shift(h),
    }
    for name, img in pairs.items():
        save_png(os.path.join(directory, name), img)
        print(os.path.join(directory, name))


def load_for_ldr_flip(path):
    """Returns (HxWx3 float32 array, inputsRGB) ready for flip_evaluator.evaluate(..., "LDR")."""
    import flip_evaluator as flip

    img = np.array(flip.load(path), dtype=np.float32, copy=True)
    if path.lower().endswith(".exr"):
        # Linear HDR: exposure 0, clamp to [0, 1]; NaN -> 0 as wavetrace does.
        img = np.nan_to_num(img, nan=0.0, posinf=1.0, neginf=0.0)
        return np.ascontiguousarray(np.clip(img, 0.0, 1.0)), False
    return np.ascontiguousarray(img), True


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("test", nargs="?")
    p.add_argument("reference", nargs="?")
    p.add_argument("--json", action="store_true", help="print a JSON object")
    p.add_argument("--pixels", nargs="*", default=[], help="also print the map at x,y")
    p.add_argument("--dump-map", metavar="FILE", help="write the map as raw little-endian f32, row-major")
    p.add_argument("--make-fixtures", metavar="DIR")
    a = p.parse_args()

    if a.make_fixtures:
        make_fixtures(a.make_fixtures)
        return 0
    if not (a.test and a.reference):
        p.error("TEST and REF are required")

    import flip_evaluator as flip

    test, test_srgb = load_for_ldr_flip(a.test)
    ref, ref_srgb = load_for_ldr_flip(a.reference)
    if test_srgb != ref_srgb:
        p.error("give two PNGs or two EXRs")
    # evaluate() converts sRGB inputs in place, so it gets copies.
    error_map, mean, params = flip.evaluate(ref.copy(), test.copy(), "LDR", inputsRGB=ref_srgb,
                                            applyMagma=False, computeMeanError=True)
    error_map = np.asarray(error_map, dtype=np.float64).reshape(ref.shape[0], ref.shape[1])
    if a.dump_map:
        error_map.astype("<f4").tofile(a.dump_map)
    pixels = {}
    for xy in a.pixels:
        x, y = (int(v) for v in xy.split(","))
        pixels[f"{x},{y}"] = float(error_map[y, x])
    result = {
        "test": a.test,
        "reference": a.reference,
        "ppd": float(params["ppd"]),
        "mean_flip": float(mean),
        "mean_flip_f64": float(error_map.mean()),
        "max_flip": float(error_map.max()),
        "pixels": pixels,
    }
    if a.json:
        print(json.dumps(result, indent=2))
    else:
        for k, v in result.items():
            print(f"{k}: {v}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
