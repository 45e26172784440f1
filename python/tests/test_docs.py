"""The README's Python example runs as written, and docs/python.md's cells run in order in one
namespace, as a notebook would run them (matplotlib draws to files: the Agg backend)."""

import os
import re

import matplotlib

from conftest import ROOT

matplotlib.use("Agg")


def python_blocks(markdown):
    return re.findall(r"```python\n(.*?)```", markdown, re.S)


def test_the_readme_example_runs_as_written(tmp_path, monkeypatch):
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## From Python") :]
    code = python_blocks(section)[0]
    assert len(code.strip().splitlines()) <= 8, code
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    assert (tmp_path / "compare.png").stat().st_size > 0


def test_the_walkthrough_runs_cell_by_cell(tmp_path, monkeypatch):
    cells = python_blocks((ROOT / "docs/python.md").read_text())
    assert len(cells) >= 5
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for i, cell in enumerate(cells):
        exec(compile(cell, f"docs/python.md cell {i + 1}", "exec"), namespace)
    assert os.path.getsize(tmp_path / "out/notebook/error.png") > 0
    assert list(namespace["df"]["spp"]) == [4, 4, 4]
