"""``wavetrace.run`` and ``wavetrace.load_report``: experiments as ``wavetrace experiment run``
runs them, their reports as Python objects."""

from __future__ import annotations

import io
import json
import os
import warnings
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _wavetrace
from .errors import InputError

ConfigLike = Union[str, "os.PathLike[str]", Mapping[str, Any]]


class ExperimentReport:
    """An experiment's report.json, read from its output directory.

    - ``directory``: the output directory; ``data``: report.json as a dict; ``status``
      (``"complete"``, or ``"running"`` for an interrupted run that ``resume=True`` continues).
    - ``runs``: one dict per run (the report's run records: id, method, label, options,
      times, ``error_metrics``, ``images``, ...).
    - ``to_pandas()``: runs.csv's table as a DataFrame (needs pandas).
    - ``image(run)``: a run's image as numpy float32 H×W×3, read when asked for.
    """

    def __init__(self, directory: Path, data: Dict[str, Any], runs_csv: str):
        self.directory = directory
        self.data = data
        self._runs_csv = runs_csv

    @property
    def runs(self) -> List[Dict[str, Any]]:
        return self.data["runs"]

    @property
    def status(self) -> str:
        return self.data["status"]

    @property
    def name(self) -> str:
        return self.data["name"]

    @property
    def failed(self) -> List[Dict[str, Any]]:
        """The runs that failed, each with its ``error``."""
        return [r for r in self.runs if r["status"] == "failed"]

    def to_pandas(self):
        """runs.csv (one row per run, the same table the command line writes) as a DataFrame."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("ExperimentReport.to_pandas() needs pandas (pip install pandas)") from e
        return pd.read_csv(io.StringIO(self._runs_csv))

    def run(self, run: Union[int, str, Mapping[str, Any]]) -> Dict[str, Any]:
        """A run's record by plan index, id or record."""
        if isinstance(run, Mapping):
            return dict(run)
        for r in self.runs:
            if (isinstance(run, int) and r["index"] == run) or r["id"] == run:
                return r
        ids = ", ".join(r["id"] for r in self.runs)
        raise InputError(f"{self.directory}: no run {run!r} (runs: {ids})")

    def image(self, run: Union[int, str, Mapping[str, Any]]) -> np.ndarray:
        """The run's image (images/RUN.exr) as numpy float32 height × width × 3."""
        record = self.run(run)
        images = record.get("images")
        if not images:
            raise InputError(f"{self.directory}: run {record['id']} has no image ({record['status']})")
        return _wavetrace.read_exr(os.fspath(self.directory / images["exr"]))

    def __repr__(self) -> str:
        return f"<wavetrace.ExperimentReport {self.name!r} {self.status}: {len(self.runs)} runs in {self.directory}>"


def load_report(directory: Union[str, "os.PathLike[str]"]) -> ExperimentReport:
    """The experiment report in ``directory`` (finished or interrupted)."""
    text, runs_csv = _wavetrace.load_report(os.fspath(directory))
    return ExperimentReport(Path(directory), json.loads(text), runs_csv)


def _overrides(set: Union[None, Sequence[str], Mapping[str, Any]]) -> List[str]:
    if set is None:
        return []
    if isinstance(set, Mapping):
        return [f"{key}={json.dumps(value)}" for key, value in set.items()]
    if isinstance(set, str):
        return [set]
    return list(set)


def run(
    config: ConfigLike,
    out: Union[None, str, "os.PathLike[str]"] = None,
    set: Union[None, Sequence[str], Mapping[str, Any]] = None,
    resume: bool = False,
    shard: Union[None, str, Tuple[int, int]] = None,
    *,
    cache: Union[None, str, "os.PathLike[str]"] = None,
    allow_other_build: bool = False,
    name: str = "experiment",
) -> ExperimentReport:
    """Run an experiment config as ``wavetrace experiment run`` does; returns its report.

    ``config``: a config file's path, or a dict in the config format (``wavetrace-experiment/1``;
    read as if it were the file ``name``.json in the working directory: relative scene paths
    are relative to it). ``out``: the output directory (default ``out/NAME``). ``set``:
    overrides as ``--set`` takes them, ``["spp=[4]", "methods.0.threads=65536"]``, or a dict
    ``{"spp": [4]}`` (values written as JSON). ``resume``: keep the finished runs of an
    interrupted attempt in ``out`` (``--resume``). ``shard``: ``"I/N"`` or ``(I, N)``.
    ``cache``: where references are cached (``--cache``; default ``$WAVETRACE_CACHE``, else
    .cache/ beside the config).

    Bad configs raise ``wavetrace.InputError`` with the command line's message. Failed runs do
    not raise: they are in the report (``failed``), with a ``RuntimeWarning`` saying so.
    Ctrl-C raises KeyboardInterrupt within a second and leaves report.json with the runs that
    finished; ``run(..., resume=True)`` continues.
    """
    if isinstance(config, Mapping):
        text: Optional[str] = json.dumps(config)
        path = Path.cwd() / f"{name}.json"
    elif isinstance(config, (str, os.PathLike)):
        text, path = None, Path(config)
    else:
        raise InputError(f"config: expected a path or a dict, got {type(config).__name__}")
    if isinstance(shard, tuple):
        shard = f"{shard[0]}/{shard[1]}"
    out_dir, failures = _wavetrace.run_experiment(
        os.fspath(path),
        text,
        None if out is None else os.fspath(out),
        _overrides(set),
        resume,
        shard,
        None if cache is None else os.fspath(cache),
        allow_other_build,
    )
    if failures:
        warnings.warn(failures, RuntimeWarning, stacklevel=2)
    return load_report(out_dir)
