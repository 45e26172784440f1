"""wavetrace from Python: render, run experiments and read reports, images as numpy arrays.

The package calls the library the ``wavetrace`` command line uses (a PyO3 extension,
``wavetrace._wavetrace``): the same renders, the same reports, the same messages.

    import wavetrace as wt
    mk = wt.render("cornell", "megakernel", 160, 120, spp=8)
    wf = wt.render("cornell", "wavefront", 160, 120, spp=8)
    wt.metrics.relmse(wf.image, mk.image)

See docs/python.md for a walkthrough.
"""

from . import metrics
from ._wavetrace import __version__
from .errors import InputError, RenderError, UnknownOptionError, WavetraceError
from .experiment import ExperimentReport, load_report, run
from .render import RenderResult, option_names, render
from .scene import Scene, export, load_scene, scenes
from . import _wavetrace


def info(adapter: "str | None" = None) -> str:
    """What ``wavetrace info`` prints: the GPU adapters wgpu sees, the one a render would use and
    why, and its features and limits. ``adapter``: prefer the one whose name contains it."""
    return _wavetrace.info(adapter)


__all__ = [
    "ExperimentReport",
    "InputError",
    "RenderError",
    "RenderResult",
    "Scene",
    "UnknownOptionError",
    "WavetraceError",
    "__version__",
    "export",
    "info",
    "load_report",
    "load_scene",
    "metrics",
    "option_names",
    "render",
    "run",
    "scenes",
]
