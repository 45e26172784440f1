"""The error metrics reports carry, on two images (numpy, height × width × 3): the library's
code (``wavetrace compare``'s and the experiment reports'), so a value here equals the report's
for the same images. Images are compared as float32, as renders are stored."""

from __future__ import annotations

import json
from typing import Any, Dict

import numpy as np

from . import _wavetrace


def _f32(a: Any) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float32)


def compare(test: Any, reference: Any, trim: float = 0.0, flip: bool = True) -> Dict[str, Any]:
    """Every metric of ``test`` against ``reference``, as a report's ``error_metrics``: mse,
    rmse, relmse, smape, mape, flip (None with ``flip=False``), and the pixel counts.
    ``trim`` drops that fraction of the largest per-pixel errors (FLIP excepted)."""
    return json.loads(_wavetrace.compare(_f32(test), _f32(reference), trim, flip))


def mse(test: Any, reference: Any) -> float:
    """mean((v − r)²) over channels and finite pixels."""
    return compare(test, reference, flip=False)["mse"]


def rmse(test: Any, reference: Any) -> float:
    """√MSE."""
    return compare(test, reference, flip=False)["rmse"]


def relmse(test: Any, reference: Any) -> float:
    """mean((v − r)² / (r + 0.01)²): pbrt-v4's MRSE, the field's relMSE."""
    return compare(test, reference, flip=False)["relmse"]


def smape(test: Any, reference: Any) -> float:
    """mean(|v − r| / (|v| + |r|)), 0/0 = 0."""
    return compare(test, reference, flip=False)["smape"]


def mape(test: Any, reference: Any) -> float:
    """mean(|v − r| / (|r| + 0.01))."""
    return compare(test, reference, flip=False)["mape"]


def flip(test: Any, reference: Any) -> float:
    """Mean LDR-FLIP of the images clamped to [0, 1] (67.02 pixels per degree)."""
    return compare(test, reference)["flip"]


def flip_map(test: Any, reference: Any) -> np.ndarray:
    """Per-pixel LDR-FLIP error, float32 height × width, in [0, 1]: an error map to plot."""
    return _wavetrace.flip_map(_f32(test), _f32(reference))
