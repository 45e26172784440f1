"""``wavetrace.render``: one render as ``wavetrace render`` makes it, with the image as a numpy
array and the report as the dict ``--report`` writes."""

from __future__ import annotations

import inspect
import json
import textwrap
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import _wavetrace
from .scene import SceneLike, load_scene

#: (name, help, default, possible values) of ``method``, ``width``, ``height``, ``spp`` and
#: every option: the ``wavetrace render`` flag's own help.
OPTION_HELP: List[Tuple[str, str, Optional[str], List[str]]] = [tuple(h) for h in _wavetrace.option_help()]
_DEFAULTS = {name: default for name, _, default, _ in OPTION_HELP}
#: Every option's default as ``render`` takes it (the knob table's values).
OPTION_DEFAULTS: Dict[str, Any] = json.loads(_wavetrace.option_defaults())


class RenderResult:
    """A finished render.

    - ``image``: numpy float32 array, height × width × 3, linear RGB: the film's values, bit for
      bit what ``wavetrace render --out`` writes to its EXR.
    - ``report``: the dict ``wavetrace render --report`` writes (schema ``wavetrace-run/1``).
    - ``seconds``: the render's time as experiments measure it (the GPU frame for GPU methods,
      the wall clock for CPU methods); ``frame_seconds``, ``wall_seconds`` and ``passes``
      (pass label → GPU seconds, GPU methods with per-pass timing) from the report.
    """

    def __init__(self, image: np.ndarray, report: Dict[str, Any]):
        self.image = image
        self.report = report

    @property
    def method(self) -> str:
        return self.report["method"]

    @property
    def frame_seconds(self) -> Optional[float]:
        """First submission to last completion (GPU methods; None for CPU methods)."""
        return self.report.get("frame_seconds")

    @property
    def wall_seconds(self) -> float:
        """Host time of the render, scene upload and pipeline creation included."""
        return self.report["wall_seconds"]

    @property
    def seconds(self) -> float:
        frame = self.frame_seconds
        return frame if frame else self.wall_seconds

    @property
    def passes(self) -> Dict[str, float]:
        """GPU seconds per pass label (empty for CPU methods)."""
        return {label: p["seconds"] for label, p in self.report.get("passes", {}).items()}

    def __repr__(self) -> str:
        s = self.report["settings"]
        return (
            f"<wavetrace.RenderResult {self.method} {self.report['scene']['name']} "
            f"{s['width']}x{s['height']} {s['spp']} spp: {self.seconds:.3f} s>"
        )


def render(
    scene: SceneLike,
    method: str = _DEFAULTS["method"],
    width: int = int(_DEFAULTS["width"]),
    height: int = int(_DEFAULTS["height"]),
    spp: int = int(_DEFAULTS["spp"]),
    *,
    progress: bool = True,
    **options: Any,
) -> RenderResult:
    # The docstring is made below from the command line's own help.
    scene = load_scene(scene)
    image, report = _wavetrace.render(scene, method, width, height, spp, options, progress)
    return RenderResult(image, json.loads(report))


def option_names() -> List[str]:
    """Every option ``render`` takes: the render settings and measurement flags, then the knob
    table's names (the names experiment configs and reports use)."""
    return list(_wavetrace.option_names())


def _doc() -> str:
    lines = [
        "Render ``scene`` with ``method`` as ``wavetrace render`` does; returns a RenderResult.",
        "",
        "``scene``: a built-in name (``wavetrace.scenes()``), a scene file's path, a dict in the JSON",
        "scene format, or a ``wavetrace.Scene``. ``progress``: the command line's progress bar",
        "(drawn only when stderr is a terminal). The GIL is released while rendering; Ctrl-C raises",
        "KeyboardInterrupt within a second. Bad values raise ``wavetrace.InputError`` (a",
        "ValueError) with the command line's message, unknown names ``UnknownOptionError``.",
        "",
        "Options (keyword arguments; the names experiment configs use, the flag's help):",
        "",
    ]
    for name, help_text, default, values in OPTION_HELP:
        head = name
        if values:
            head += " : " + " | ".join(values)
        if name in OPTION_DEFAULTS:
            head += f" = {OPTION_DEFAULTS[name]!r}"
        elif default is not None:
            head += f" = {default}"
        lines.append(head)
        body = " ".join(help_text.split()) or "(see docs/cli-and-configs.md)"
        lines.extend(textwrap.wrap(body, 92, initial_indent="    ", subsequent_indent="    "))
    return "\n".join(lines)


render.__doc__ = _doc()
render.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
    list(inspect.signature(render).parameters.values())[:-1]
    + [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=OPTION_DEFAULTS[name])
        for name in _wavetrace.option_names()
    ]
)
