"""The metrics on two arrays are `wavetrace compare`'s on the same images."""

import json

import numpy as np
import pytest

import wavetrace as wt
from conftest import SMALL


def test_metrics_are_the_clis(cli, tmp_path):
    a = wt.render("three-spheres", "cpu", **SMALL, seed=1)
    b = wt.render("three-spheres", "cpu", **SMALL, seed=2)
    for r, name in ((a, "a"), (b, "b")):
        cli("render", "--scene", "three-spheres", "--method", "cpu", "--width", SMALL["width"], "--height", SMALL["height"], "--spp", SMALL["spp"], "--seed", 1 if name == "a" else 2, "--out", tmp_path / f"{name}.exr")
    expected = json.loads(cli("compare", tmp_path / "a.exr", tmp_path / "b.exr", "--json").stdout)["metrics"]
    assert wt.metrics.compare(a.image, b.image) == expected
    assert wt.metrics.relmse(a.image, b.image) == expected["relmse"] > 0
    assert wt.metrics.flip(a.image, b.image) == expected["flip"]
    for name in ("mse", "rmse", "smape", "mape"):
        assert getattr(wt.metrics, name)(a.image, b.image) == expected[name]
    m = wt.metrics.flip_map(a.image, b.image)
    assert m.shape == a.image.shape[:2] and m.dtype == np.float32
    assert np.isclose(m.mean(dtype=np.float64), expected["flip"], rtol=1e-6)


def test_bad_images_are_named():
    with pytest.raises(wt.InputError, match="size"):
        wt.metrics.relmse(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))
    with pytest.raises(wt.InputError, match=r"test: expected an array of shape \(height, width, 3\)"):
        wt.metrics.relmse(np.zeros((4, 4, 4)), np.zeros((4, 4, 4)))
