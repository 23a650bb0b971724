"""The bundled scenes: where they live and how to load them.

The MJCF files are in the repository's ``scenes/`` folder (shipped inside the wheel as
``redik/_scenes``). :mod:`redik.models.scene_library` holds the tables they are generated from.
"""

from __future__ import annotations

import os
from pathlib import Path

from redik.core.exceptions import InvalidInput, ModelError
from redik.models import registry

_PACKAGE = Path(__file__).resolve().parents[1]  # redik/


def scenes_dir() -> Path:
    """The folder holding the bundled scene files."""
    for candidate in (_PACKAGE / "_scenes", _PACKAGE.parent / "scenes"):
        if candidate.is_dir():
            return candidate
    raise ModelError(f"bundled scenes not found next to {_PACKAGE}")


def list_scenes() -> list[str]:
    """Names of the bundled scenes (file stems), sorted."""
    return sorted(path.stem for path in scenes_dir().glob("*.xml"))


# Prefixes naming a model of an installed third-party package, e.g. ``"example-robot-data:ur5"``.
_THIRD_PARTY = {
    "example-robot-data": registry.example_robot_data,
    "pybullet_data": registry.pybullet_data,
}


def scene_path(name: str | os.PathLike[str]) -> Path:
    """Path of a scene given its bundled name, a file path, or a third-party model's name.

    ``"panda"``, a path to any MJCF/URDF file, or ``"example-robot-data:<name>"`` /
    ``"pybullet_data:<name>"`` (:mod:`redik.models`).

    Raises:
        InvalidInput: ``name`` is neither a string nor a path.
        ModelError: no bundled scene has that name and no file has that path.
    """
    if not isinstance(name, str | os.PathLike) or not str(name).strip():
        raise InvalidInput(
            f"a robot is named by a bundled scene name (one of {list_scenes()}), the path of "
            f"an MJCF/URDF file or 'example-robot-data:<name>', got {name!r} (the scene name)"
        )
    path = Path(name)
    package, colon, model = str(name).partition(":")
    if colon and package in _THIRD_PARTY:
        return _THIRD_PARTY[package](model)
    try:
        is_file = path.is_file()
        exists = is_file or path.exists()
    except (OSError, ValueError):  # a name too long for the file system, or a NUL byte
        is_file = exists = False
    if path.suffix in (".xml", ".urdf", ".mjcf") or exists:
        if not is_file:
            raise ModelError(f"robot file not found: {str(path)!r}")
        return path
    bundled = scenes_dir() / f"{name}.xml"
    try:
        found = bundled.is_file()
    except (OSError, ValueError):
        found = False
    if not found:
        raise ModelError(
            f"no bundled scene named {str(name)[:200]!r} and no file at that path; bundled "
            f"scenes: {list_scenes()} (or give the path of an MJCF/URDF file)"
        )
    return bundled
