"""Shared fixtures of the Python package's tests (run by scripts/test.sh after `maturin
develop`, on the software driver where there is no GPU). Renders are tiny: the suite's time
budget is tight, and what these tests check (the same film, report and message as the command
line) does not depend on size."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import wavetrace as wt

ROOT = Path(__file__).resolve().parents[2]

# Every GPU render here: no timed warm-up (0.5 s of frames at least), as small as shows the method.
SMALL = dict(width=24, height=16, spp=2)


@pytest.fixture(scope="session")
def cli():
    """Runs the `wavetrace` binary the package was built beside; returns the completed process."""
    binary = os.environ.get("WAVETRACE_BIN", str(ROOT / "target/release/wavetrace"))
    if not Path(binary).is_absolute():
        binary = str(ROOT / binary)

    def run(*args, check=True):
        p = subprocess.run([binary, *map(str, args)], capture_output=True, text=True, cwd=ROOT)
        if check and p.returncode != 0:
            raise AssertionError(f"wavetrace {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p

    return run


def read_json(path):
    return json.loads(Path(path).read_text())


def cli_error(process):
    """The message of `error: ...`, the command line's last stderr line."""
    assert process.returncode != 0, process.stdout
    line = process.stderr.strip().splitlines()[-1]
    assert line.startswith("error: "), process.stderr
    return line[len("error: "):]


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


@pytest.fixture(scope="session")
def wavetrace():
    return wt
