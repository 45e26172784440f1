"""wavetrace.run and load_report: a config dict with `set`, its runs as records and a
DataFrame, a run's image, and the metrics the report carries computed again from Python."""

import json
import warnings

import numpy as np
import pytest

import wavetrace as wt
from conftest import bits, cli_error


def config(**over):
    c = {
        "schema": "wavetrace-experiment/1",
        "question": "Does the Python front end run a config dict?",
        "scenes": ["three-spheres"],
        "resolutions": ["16x12"],
        "spp": [4],
        "repetitions": 1,
        "warmup": 0,
        "methods": [{"method": "cpu"}, {"method": "megakernel"}],
        "reference": {"method": "cpu-f64", "spp": 8},
    }
    c.update(over)
    return c


def test_a_config_dict_with_set_runs_and_reports(tmp_path):
    out = tmp_path / "out"
    r = wt.run(config(), out=out, set={"spp": [2]}, cache=tmp_path / "cache")
    assert r.status == "complete" and r.data["overrides"] == ["spp=[2]"]
    assert [(x["method"], x["spp"], x["status"]) for x in r.runs] == [("cpu", 2, "ok"), ("megakernel", 2, "ok")]
    df = r.to_pandas()
    assert list(df["method"]) == ["cpu", "megakernel"] and "relmse" in df.columns
    again = wt.load_report(out)
    assert again.data == r.data
    image = r.image(0)
    assert image.shape == (12, 16, 3) and image.dtype == np.float32
    # The report's error metrics are the package's metrics of the run's image against the
    # reference the report names: the same code.
    ref_exr = next((out / "references").glob("*.exr"))
    reference = wt._wavetrace.read_exr(str(ref_exr))
    for run in r.runs:
        assert wt.metrics.compare(r.image(run["id"]), reference) == run["error_metrics"], run["id"]
    with pytest.raises(wt.InputError, match="no run 'nope'"):
        r.image("nope")


def test_bad_configs_and_overrides_raise_the_clis_message(cli, tmp_path):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(config()))
    for set_ in (["spp=[0]"], ["methods.0.tial=off"]):
        with pytest.raises(wt.InputError) as e:
            wt.run(path, out=tmp_path / "o", set=set_)
        p = cli("experiment", "run", path, "--out", tmp_path / "o", "--set", set_[0], check=False)
        assert str(e.value) == cli_error(p)
    with pytest.raises(wt.InputError, match="shard"):
        wt.run(path, out=tmp_path / "o", shard="3/2")
    with pytest.raises(wt.InputError, match="not an experiment report|reading"):
        wt.load_report(tmp_path / "nowhere")


def test_failed_runs_warn_with_the_clis_message(tmp_path):
    c = config(methods=[{"method": "cpu"}, {"method": "megakernel"}], adapter="no-such-adapter")
    del c["reference"]
    with pytest.warns(RuntimeWarning, match="1 of 2 runs failed; report.json and report.html say why"):
        r = wt.run(c, out=tmp_path / "o")
    assert r.status == "complete"
    assert [x["method"] for x in r.failed] == ["megakernel"] and "no-such-adapter" in r.failed[0]["error"]
