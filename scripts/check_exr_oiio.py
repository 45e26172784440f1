#!/usr/bin/env python3
"""Open an EXR with OpenImageIO, print its spec and attributes, and optionally check it.

    python scripts/check_exr_oiio.py IMAGE.exr [EXPECTED.json]

EXPECTED.json is what the `oiio_fixture` test in tests/image_io.rs writes: width, height,
the RGB values as f32 bit patterns (so NaN, infinities and -0.0 compare exactly) and the text
attributes. Exits non-zero if OIIO cannot open the file or anything differs.
Needs `pip install OpenImageIO numpy`.
"""
import json
import sys

import numpy as np
import OpenImageIO as oiio


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    path = sys.argv[1]

    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"{path}: OIIO cannot open: {oiio.geterror()}")
    spec = inp.spec()
    print(f"OpenImageIO {oiio.VERSION_STRING}, reader {inp.format_name()}")
    print(f"{path}: {spec.width}x{spec.height}, {spec.nchannels} channels "
          f"{list(spec.channelnames)}, format {spec.format}, "
          f"per-channel {[str(f) for f in spec.channelformats] or 'uniform'}, "
          f"tile {spec.tile_width}x{spec.tile_height}")
    for attr in spec.extra_attribs:
        print(f"  {attr.name} ({attr.type}) = {attr.value!r}")
    # Read the file's own float32 samples; asking for FLOAT avoids any conversion.
    pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    inp.close()
    if pixels is None:
        sys.exit(f"{path}: OIIO cannot read pixels: {oiio.geterror()}")
    pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    finite = pixels[np.isfinite(pixels)]
    print(f"  pixels: {pixels.size} samples, {np.isnan(pixels).sum()} NaN, "
          f"{np.isinf(pixels).sum()} inf, finite min {finite.min():g} max {finite.max():g} "
          f"mean per channel {[float(m) for m in np.nanmean(np.where(np.isinf(pixels), np.nan, pixels), axis=(0, 1))]}")

    if len(sys.argv) == 3:
        check(path, spec, pixels, sys.argv[2])


def check(path, spec, pixels, expected_path):
    with open(expected_path, encoding="utf-8") as f:
        expected = json.load(f)
    failures = []
    if (spec.width, spec.height) != (expected["width"], expected["height"]):
        failures.append(f"size {spec.width}x{spec.height}, expected "
                        f"{expected['width']}x{expected['height']}")
    if spec.format != oiio.FLOAT:
        failures.append(f"format {spec.format}, expected float")
    names = list(spec.channelnames)
    if not {"R", "G", "B"} <= set(names):
        failures.append(f"channels {names}, expected R, G, B")
    if not failures:
        rgb = pixels[:, :, [names.index(c) for c in "RGB"]]
        got = np.ascontiguousarray(rgb).view(np.uint32).ravel()
        want = np.array(expected["rgb_f32_bits"], dtype=np.uint32)
        differing = np.flatnonzero(got != want)
        if differing.size:
            i = differing[0]
            failures.append(f"{differing.size} samples differ; first at index {i}: "
                            f"{got[i]:#010x}, expected {want[i]:#010x}")
        else:
            print(f"  all {want.size} RGB samples bit-identical to what wavetrace wrote")
    for name, value in expected["attributes"].items():
        got = spec.getattribute(name)
        if got != value:
            failures.append(f"attribute {name} = {got!r}, expected {value!r}")
    if failures:
        sys.exit(f"{path}: MISMATCH\n  " + "\n  ".join(failures))
    print(f"  all {len(expected['attributes'])} text attributes match")


if __name__ == "__main__":
    main()
