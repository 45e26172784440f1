"""wavetrace.render against `wavetrace render`: the same film bit for bit, the same report, the
same option names and messages."""

import math
import threading
import time

import numpy as np
import pytest

import wavetrace as wt
from conftest import SMALL, bits, cli_error, read_json

# Keys whose values are measured times (or derived from them): equal only in shape.
TIMED = ("_seconds", "per_second")


def untimed(v, key=""):
    """The report with every measured time replaced by its type."""
    if isinstance(v, dict):
        if key in ("warmup",):
            return sorted(v)
        return {k: untimed(x, k) for k, x in v.items()}
    if isinstance(v, list):
        return [untimed(x, key) for x in v]
    if key.endswith(TIMED) or key == "seconds":
        return type(v).__name__
    return v


CASES = [
    ("cpu", [], {}),
    ("megakernel", ["--nee", "on", "--roulette", "on", "--max-depth", "8"], {"nee": True, "roulette": "on", "max_depth": 8}),
    (
        "wavefront",
        ["--schedule", "regenerate", "--tail", "megakernel", "--compaction-method", "scan", "--seed", "3"],
        {"schedule": "regenerate", "tail": "megakernel", "compaction": "scan", "seed": 3},
    ),
]


@pytest.mark.parametrize("method,flags,options", CASES, ids=[c[0] for c in CASES])
def test_the_image_and_report_are_the_clis(cli, tmp_path, method, flags, options):
    exr, report = tmp_path / "cli.exr", tmp_path / "cli.json"
    size = ["--width", SMALL["width"], "--height", SMALL["height"], "--spp", SMALL["spp"]]
    cli("render", "--scene", "three-spheres", "--method", method, *size, "--warmup", 0, *flags, "--out", exr, "--report", report)
    r = wt.render("three-spheres", method, **SMALL, warmup=0, **options)

    assert r.image.dtype == np.float32 and r.image.shape == (SMALL["height"], SMALL["width"], 3)
    assert np.array_equal(bits(r.image), bits(wt._wavetrace.read_exr(str(exr))))
    expected = read_json(report)
    assert untimed(r.report) == untimed(expected)
    if method == "cpu":
        assert r.frame_seconds is None and r.passes == {} and r.seconds == r.wall_seconds
    else:
        assert r.seconds == r.frame_seconds > 0
        assert set(r.passes) == set(expected["passes"]) and all(s >= 0 for s in r.passes.values())


def test_scenes_by_name_file_and_dict_render_alike(tmp_path):
    scene = wt.export("three-spheres")
    assert scene["format"] == "wavetrace-scene/1"
    path = tmp_path / "mine.json"
    path.write_text(__import__("json").dumps(scene))
    images = [wt.render(s, "cpu", **SMALL).image for s in ("three-spheres", path, scene, wt.load_scene(scene))]
    for image in images[1:]:
        assert np.array_equal(bits(image), bits(images[0]))
    assert wt.load_scene(path).name == "mine"


def test_gltf_and_builtin_listing():
    from conftest import ROOT

    tetra = wt.load_scene(ROOT / "experiments/scenes/tetrahedra.gltf")
    assert tetra.primitives > 0 and tetra.name == "tetrahedra"
    names = [n for n, _ in wt.scenes()]
    assert "cornell" in names and "three-spheres" in names


def test_every_option_is_documented_and_in_the_signature():
    import inspect

    names = wt.option_names()
    assert {"tail", "workgroup_size", "pool_size", "nee", "warmup", "ray_offset"} <= set(names)
    params = inspect.signature(wt.render).parameters
    doc = wt.render.__doc__
    for name in names:
        assert name in params, name
        assert f"\n{name}" in doc, name


def test_the_stub_is_generated_from_the_options_table():
    from pathlib import Path

    from wavetrace import _stubgen

    stub = Path(wt.__file__).with_name("render.pyi").read_text()
    assert stub == _stubgen.stub(), "python -m wavetrace._stubgen > python/wavetrace/render.pyi"


RULES = [
    {"method": "wavefront", "tail": "megakernel"},
    {"method": "megakernel", "threads": 64},
    {"method": "cpu", "spp": 0},
    {"method": "cpu", "width": 0},
]


@pytest.mark.parametrize("kw", RULES, ids=["tail", "threads", "spp", "width"])
def test_bad_values_raise_the_clis_message(cli, tmp_path, kw):
    kw = {**SMALL, "warmup": 0, **kw}
    with pytest.raises(wt.InputError) as e:
        wt.render("three-spheres", **kw)
    assert isinstance(e.value, ValueError)
    flags = [x for name, v in kw.items() for x in (f"--{name.replace('_', '-')}", v)]
    p = cli("render", "--scene", "three-spheres", *flags, "--out", tmp_path / "x.exr", check=False)
    assert str(e.value) == cli_error(p)


def test_bad_scenes_raise_the_clis_message(cli, tmp_path):
    with pytest.raises(wt.InputError) as e:
        wt.render("three-sphere", "cpu", **SMALL)
    p = cli("render", "--scene", "three-sphere", "--method", "cpu", "--out", tmp_path / "x.exr", check=False)
    assert str(e.value) == cli_error(p)
    assert "did you mean" in str(e.value)
    broken = wt.export("three-spheres")
    broken["objects"][0]["radius"] = -1
    with pytest.raises(wt.InputError, match=r"<dict>: objects\[0\]\.radius"):
        wt.render(broken, "cpu", **SMALL)
    with pytest.raises(wt.InputError, match="expected a built-in name"):
        wt.render(42, "cpu", **SMALL)


def test_bad_names_and_values_are_named():
    with pytest.raises(wt.UnknownOptionError, match='unknown option "tial" \\(did you mean "tail"\\?\\)') as e:
        wt.render("three-spheres", "wavefront", **SMALL, tial="off")
    assert isinstance(e.value, TypeError) and isinstance(e.value, ValueError)
    bad = [
        ({"compaction": "scna"}, 'compaction: unknown value "scna" (did you mean "scan"?)'),
        ({"nee": 3}, "nee: expected True, False"),
        ({"workgroup_size": -1}, "workgroup_size: expected a whole number"),
        ({"preheat": 99}, "--preheat: the preheat must be 0 to 10 seconds, got 99"),
        ({"translate": [1, 2]}, "translate: expected a number D"),
        ({"scale": math.nan}, "scale: expected a finite number"),
        ({"adapter": object()}, "adapter: cannot take a value of type object"),
        ({"spp": 2.5}, "spp: expected a whole number"),
    ]
    for options, message in bad:
        kw = {**SMALL, **options}
        with pytest.raises(wt.InputError) as e:
            wt.render("three-spheres", "wavefront", **kw)
        assert str(e.value).startswith(message), (options, str(e.value))
    with pytest.raises(wt.InputError, match='method: unknown value "gpu"'):
        wt.render("three-spheres", "gpu", **SMALL)


def test_no_panic_crosses_into_python():
    with pytest.raises(wt.WavetraceError, match=r"internal error \(panic\): test panic") as e:
        wt._wavetrace._panic("test panic")
    assert not isinstance(e.value, (ValueError, RuntimeError))


def test_the_gil_is_released_while_rendering():
    ticks = 0
    done = threading.Event()

    def tick():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        before = ticks
        start = time.perf_counter()
        wt.render("cornell", "cpu", 64, 48, spp=64, progress=False)
        seconds, during = time.perf_counter() - start, ticks - before
    finally:
        done.set()
        t.join()
    # With the GIL held the ticking thread could not run while the render did.
    assert during >= 10, (during, seconds)


def test_info_is_what_the_cli_prints(cli):
    assert wt.info() == cli("info").stdout
