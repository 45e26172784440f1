#!/usr/bin/env python3
"""`wavetrace render ARGS` through the Python package (`wavetrace.render`), for timing Python
against the command line on the same job with scripts/interleave.py:

    scripts/interleave.py --rounds 7 --scene rtiow-final --method wavefront --width 320 \\
        --height 180 --spp 16 -v cli -v python --bin=scripts/python_render.py

Takes the command line's flags (`--scene`, `--method`, the sizes, each option as `--name VALUE`,
`--instrument`), renders once in this process, and writes `--report FILE` as the command line
does (`--out` is taken and ignored: the image is not what is timed). Runs itself under
target/exr-venv's Python (WAVETRACE_PYTHON overrides it) when the package is not importable.
"""
import json
import os
import sys

try:
    import wavetrace
except ImportError:
    if os.environ.get("PYTHON_RENDER_REEXECUTED"):
        raise
    os.environ["PYTHON_RENDER_REEXECUTED"] = "1"
    python = os.environ.get("WAVETRACE_PYTHON", "target/exr-venv/bin/python")
    os.execv(python, [python, __file__, *sys.argv[1:]])


def value(text):
    """A flag's value as the option takes it: JSON where it reads as JSON, else the text."""
    if "," in text:
        return [value(t) for t in text.split(",")]
    try:
        return json.loads(text)
    except ValueError:
        return text


def main(argv):
    if argv[:1] == ["render"]:
        argv = argv[1:]
    flags, i = {}, 0
    while i < len(argv):
        name = argv[i][2:].replace("-", "_")
        if name == "instrument":
            flags[name], i = True, i + 1
        else:
            flags[name], i = argv[i + 1], i + 2
    flags.pop("out", None)
    report = flags.pop("report", None)
    on = flags.pop("compaction", "on")
    how = flags.pop("compaction_method", "atomic")
    options = {k: value(v) if isinstance(v, str) else v for k, v in flags.items()}
    options["compaction"] = "off" if on == "off" else how
    scene, method = options.pop("scene"), options.pop("method", "megakernel")
    result = wavetrace.render(scene, method, **options)
    if report:
        with open(report, "w") as f:
            json.dump(result.report, f, indent=2)


if __name__ == "__main__":
    main(sys.argv[1:])
