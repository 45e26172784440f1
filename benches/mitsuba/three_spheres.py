#!/usr/bin/env python3
"""Mitsuba 3 (scalar_rgb) throughput on wavetrace's built-in "three-spheres" scene.

Builds the scene with mi.load_dict, renders it with the `path` integrator and prints one JSON
object to stdout (diagnostics go to stderr). Only the timed mi.render call is counted; scene
loading and an optional tiny warm-up render are not.

See README.md beside this file for what is and is not equivalent to wavetrace's CPU reference.
"""

import argparse
import json
import math
import os
import resource
import sys
import time

import numpy as np


def sky_envmap(height: int = 256, width: int = 8) -> np.ndarray:
    """Equirectangular RGB bitmap of the book's sky gradient.

    Mitsuba's envmap (default to_world, +Y up) looks up direction v at
    uv = (atan2(v.x, -v.z) / 2pi, acos(v.y) / pi): row 0 is +Y (zenith), the last row -Y.
    The gradient depends only on v.y, so every column is the same. Rows are sampled at their
    centres; Mitsuba interpolates bilinearly between them, and the gradient is smooth in theta,
    so 256 rows keep the error far below the render noise (checked by --check-sky).
    """
    theta = (np.arange(height) + 0.5) / height * math.pi
    dy = np.cos(theta)
    a = 0.5 * (dy + 1.0)
    white = np.ones(3)
    blue = np.array([0.5, 0.7, 1.0])
    row = (1.0 - a)[:, None] * white[None, :] + a[:, None] * blue[None, :]
    return np.ascontiguousarray(np.repeat(row[:, None, :], width, axis=1), dtype=np.float32)


def sky_exact(d):
    d = np.asarray(d, dtype=np.float64)
    d = d / np.linalg.norm(d)
    a = 0.5 * (d[1] + 1.0)
    return (1.0 - a) * np.ones(3) + a * np.array([0.5, 0.7, 1.0])


def scene_dict(mi, width, height, spp, max_depth, background):
    lookfrom, lookat, vup = [13.0, 2.0, 3.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]
    vfov = 20.0
    defocus_angle = 0.6
    focus_dist = 10.0
    # RTIOW 4th edition: the defocus disk's radius is focus_dist * tan(defocus_angle / 2).
    lens_radius = focus_dist * math.tan(math.radians(defocus_angle / 2.0))

    def rgb(c):
        return {"type": "rgb", "value": c}

    def sphere(center, radius, bsdf):
        return {"type": "sphere", "center": center, "radius": radius, "bsdf": bsdf}

    if background == "envmap":
        emitter = {"type": "envmap", "bitmap": mi.Bitmap(sky_envmap())}
    else:
        # Mean of the gradient over the sphere of directions: a = 0.5 on average.
        emitter = {"type": "constant", "radiance": rgb([0.75, 0.85, 1.0])}

    return {
        "type": "scene",
        "integrator": {
            "type": "path",
            # Mitsuba's max_depth is the longest path in segments (rays): 1 = directly visible
            # emitters only, the same count as wavetrace's --max-depth (rays per path).
            "max_depth": max_depth,
            # Russian roulette starts at this depth; past max_depth it never happens.
            "rr_depth": max_depth + 1000,
            "hide_emitters": False,
        },
        "sensor": {
            "type": "thinlens",
            "fov": vfov,
            "fov_axis": "y",
            "aperture_radius": lens_radius,
            "focus_distance": focus_dist,
            "to_world": mi.ScalarTransform4f().look_at(origin=lookfrom, target=lookat, up=vup),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
                "component_format": "float32",
            },
        },
        "sky": emitter,
        "ground": sphere([0.0, -1000.0, 0.0], 1000.0, {"type": "diffuse", "reflectance": rgb([0.5, 0.5, 0.5])}),
        "glass": sphere([0.0, 1.0, 0.0], 1.0, {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}),
        "diffuse": sphere([-4.0, 1.0, 0.0], 1.0, {"type": "diffuse", "reflectance": rgb([0.4, 0.2, 0.1])}),
        # material "none": eta 0, k 1, i.e. Fresnel reflectance 1 at every angle (a perfect
        # mirror) scaled by specular_reflectance, like the book's metal with fuzz 0.
        "metal": sphere(
            [4.0, 1.0, 0.0],
            1.0,
            {"type": "conductor", "material": "none", "specular_reflectance": rgb([0.7, 0.6, 0.5])},
        ),
    }


def check_sky(mi):
    """Evaluates the envmap against the exact gradient in a spread of directions."""
    scene = mi.load_dict({"type": "scene", "sky": {"type": "envmap", "bitmap": mi.Bitmap(sky_envmap())}})
    env = scene.emitters()[0]
    worst = 0.0
    rng = np.random.default_rng(1)
    for _ in range(2000):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*(-d))  # wi points back toward the scene; the emitter is seen along d
        got = np.array(env.eval(si))
        worst = max(worst, float(np.max(np.abs(got - sky_exact(d)))))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--width", type=int, default=400)
    ap.add_argument("--height", type=int, default=225)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=50, help="longest path in rays (wavetrace's convention)")
    ap.add_argument("--threads", type=int, default=0, help="worker threads (0: Mitsuba's default, all cores)")
    ap.add_argument("--background", choices=["envmap", "constant"], default="envmap")
    ap.add_argument("--no-warmup", action="store_true", help="skip the untimed 1-spp 64x36 warm-up render")
    ap.add_argument("--out", help="write the image as EXR (linear RGB)")
    ap.add_argument("--png", help="write an sRGB 8-bit PNG preview")
    ap.add_argument("--check-sky", action="store_true", help="also report the envmap's worst error vs the exact gradient")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    if args.threads > 0:
        dr.set_thread_count(args.threads)
    threads = dr.thread_count()

    extra = {}
    if args.check_sky:
        extra["sky_max_abs_error"] = check_sky(mi)

    scene = mi.load_dict(scene_dict(mi, args.width, args.height, args.spp, args.max_depth, args.background))

    if not args.no_warmup:
        warm = mi.load_dict(scene_dict(mi, 64, 36, 1, args.max_depth, args.background))
        mi.render(warm, spp=1)

    ru0 = resource.getrusage(resource.RUSAGE_SELF)
    t0 = time.perf_counter()
    image = mi.render(scene, spp=args.spp)
    seconds = time.perf_counter() - t0
    ru1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu_seconds = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)

    arr = np.array(image, dtype=np.float64)
    samples = args.width * args.height * args.spp
    report = {
        "renderer": "mitsuba3 scalar_rgb",
        "version": mi.__version__,
        "drjit_version": dr.__version__,
        "scene": "three-spheres",
        "background": "envmap (256x8 equirect sky gradient)" if args.background == "envmap" else "constant (0.75,0.85,1.0)",
        "integrator": "path (NEE+MIS, RR off)",
        "width": args.width,
        "height": args.height,
        "spp": args.spp,
        "max_depth": args.max_depth,
        "samples": samples,
        "seconds": seconds,
        "samples_per_second": samples / seconds,
        "threads": threads,
        "cpu_seconds": cpu_seconds,
        "cpu_utilisation": cpu_seconds / seconds,
        "logical_cpus": os.cpu_count(),
        "image_mean": float(arr.mean()),
        "nonfinite_pixels": int((~np.isfinite(arr)).any(axis=-1).sum()),
    }
    report.update(extra)

    if args.out:
        mi.Bitmap(image).write(args.out)
    if args.png:
        bmp = mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True)
        bmp.write(args.png)

    json.dump(report, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
