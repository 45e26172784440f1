"""Scenes: a built-in name, a scene file (JSON, glTF ``.gltf``/``.glb``; OBJ meshes through a
JSON scene's ``mesh`` objects), or a dict in the JSON scene format (``wavetrace-scene/1``, as
``wavetrace scene export`` writes it)."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Tuple, Union

from . import _wavetrace
from .errors import InputError

Scene = _wavetrace.Scene
SceneLike = Union["Scene", str, "os.PathLike[str]", Dict[str, Any]]


def load_scene(scene: SceneLike, name: Optional[str] = None) -> Scene:
    """The scene ``scene`` names, loaded and checked as ``--scene`` loads it.

    ``scene``: a ``Scene`` (returned as it is), a built-in name (``scenes()``), a path to a
    scene file, or a dict in the JSON scene format (``name`` names it, default ``"scene"``;
    mesh paths in it are relative to the working directory).
    """
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        try:
            text = json.dumps(scene)
        except (TypeError, ValueError) as e:
            raise InputError(f"<dict>: not JSON: {e}") from None
        return _wavetrace.scene_from_json(text, name or "scene")
    if isinstance(scene, (str, os.PathLike)):
        return _wavetrace.load_scene(os.fspath(scene))
    raise InputError(
        f"scene: expected a built-in name, a path, a dict or a wavetrace.Scene, got {type(scene).__name__}"
    )


def export(scene: SceneLike) -> Dict[str, Any]:
    """The scene as a dict in the JSON scene format; ``render`` and ``load_scene`` take it back."""
    return load_scene(scene).export()


def scenes() -> List[Tuple[str, str]]:
    """The built-in scenes as (name, description) pairs, as ``wavetrace scene list``."""
    return list(_wavetrace.builtin_scenes())
