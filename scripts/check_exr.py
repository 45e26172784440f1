#!/usr/bin/env python3
"""Read wavetrace's EXRs with a third-party reader and check them against what wavetrace wrote.

    python scripts/check_exr.py IMAGE.exr EXPECTED.json [IMAGE.exr EXPECTED.json ...]

The reader is the OpenEXR project's own Python bindings (`pip install OpenEXR numpy`;
scripts/exr_reader.sh makes a venv with them), and OpenImageIO as well where its bindings are
installed. EXPECTED.json is what tests/suite/exr_third_party.rs writes: width, height, the RGB
values as f32 bit patterns (so NaN, infinities and -0.0 compare exactly) and the text attributes
(wavetrace.* and the standard ones); optionally `"values_in": [LO, HI]` (every sample within, and
both ends met exactly: the furnace scene's exact image). The channels must be exactly R, G, B of
32-bit float. Prints what it checked; exits non-zero, naming the file and what differs, if a
reader cannot open the file or anything differs.
"""
import json
import sys

import numpy as np
import OpenEXR

try:
    import OpenImageIO as oiio
except ImportError:
    oiio = None


def read_openexr(path):
    """(width, height, channel names, {name: dtype}, HxWx3 float32 RGB, {attribute: text})."""
    with OpenEXR.File(path, separate_channels=True) as f:
        header = f.header()
        channels = f.channels()
        (x0, y0), (x1, y1) = header["dataWindow"]
        width, height = int(x1 - x0 + 1), int(y1 - y0 + 1)
        names = sorted(channels)
        dtypes = {n: str(channels[n].pixels.dtype) for n in names}
        rgb = None
        if {"R", "G", "B"} <= set(names):
            rgb = np.stack([np.asarray(channels[c].pixels) for c in "RGB"], axis=-1)
        text = {k: v for k, v in header.items() if isinstance(v, str)}
    return width, height, names, dtypes, rgb, text


def read_oiio(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise RuntimeError(f"OpenImageIO cannot open: {oiio.geterror()}")
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    inp.close()
    if pixels is None:
        raise RuntimeError(f"OpenImageIO cannot read pixels: {oiio.geterror()}")
    names = list(spec.channelnames)
    pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    rgb = pixels[:, :, [names.index(c) for c in "RGB"]] if {"R", "G", "B"} <= set(names) else None
    text = {a.name: a.value for a in spec.extra_attribs if isinstance(a.value, str)}
    return spec.width, spec.height, sorted(names), {n: "float32" for n in names}, rgb, text


def check(reader, path, read, expected):
    failures = []
    try:
        width, height, names, dtypes, rgb, text = read(path)
    except Exception as e:  # any reader error is a failed check, with its message
        return [f"{reader} cannot read it: {type(e).__name__}: {e}"]
    if (width, height) != (expected["width"], expected["height"]):
        failures.append(f"size {width}x{height}, expected {expected['width']}x{expected['height']}")
    if names != ["B", "G", "R"]:
        failures.append(f"channels {names}, expected exactly R, G, B")
    wrong_type = {n: t for n, t in dtypes.items() if t != "float32"}
    if wrong_type:
        failures.append(f"channel types {wrong_type}, expected 32-bit float")
    if rgb is not None and not failures:
        got = np.ascontiguousarray(rgb, dtype=np.float32).view(np.uint32).ravel()
        want = np.array(expected["rgb_f32_bits"], dtype=np.uint32)
        differing = np.flatnonzero(got != want)
        if differing.size:
            i = differing[0]
            failures.append(f"{differing.size} of {want.size} samples differ; first at index {i} "
                            f"(pixel {i // 3 % width}, {i // 3 // width}, channel {'RGB'[i % 3]}): "
                            f"{got[i]:#010x}, expected {want[i]:#010x}")
        if "values_in" in expected:
            lo, hi = expected["values_in"]
            v = rgb.astype(np.float64)
            if not (np.all(v >= lo) and np.all(v <= hi)):
                failures.append(f"samples outside [{lo}, {hi}]: min {v.min()}, max {v.max()}")
            elif not (np.any(v == lo) and np.any(v == hi)):
                failures.append(f"neither end of [{lo}, {hi}] met exactly (min {v.min()}, max {v.max()})")
    for name, value in expected["attributes"].items():
        if text.get(name) != value:
            failures.append(f"attribute {name} = {text.get(name)!r}, expected {value!r}")
    if not failures:
        print(f"{path}: {reader}: {width}x{height} R, G, B float32, {width * height * 3} samples "
              f"bit-identical, {len(expected['attributes'])} attributes match")
    return failures


def main():
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.exit(__doc__)
    readers = [(f"OpenEXR {OpenEXR.__version__}", read_openexr)]
    if oiio is not None:
        readers.append((f"OpenImageIO {oiio.VERSION_STRING}", read_oiio))
    failed = False
    for path, expected_path in zip(args[::2], args[1::2]):
        with open(expected_path, encoding="utf-8") as f:
            expected = json.load(f)
        for reader, read in readers:
            failures = check(reader, path, read, expected)
            if failures:
                failed = True
                print(f"{path}: {reader}: MISMATCH\n  " + "\n  ".join(failures), file=sys.stderr)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
