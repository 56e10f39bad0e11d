"""The files a case names, and moving a case between folders without breaking them.

A case names files by path: its material (a lab table or a material.nc; a bare name such as
``powernet`` is a bundled table, not a path), a mesh body's mesh and its smooth surface, a
torso's or a leg's size chart, an avatar's chart and mesh, and a worn pattern's file or the
files of the body it was cut for (``garment.pattern``). A case file's relative paths
resolve against the case file's own folder (`cloth.stages.case`), so a case the tool writes
stores them relative to the folder it is written into (`relocated`): it then runs as written
from any working directory, and a folder holding the case and its files can be moved as a
whole. An absolute path stays absolute.
"""

from __future__ import annotations

import copy
import os
from pathlib import Path
from typing import Any

#: The keys of a body block that hold a path, from the block.
BODY_PATH_KEYS: tuple[tuple[str, ...], ...] = (
    ("mesh",),
    ("surface_file",),
    ("torso", "chart"),
    ("leg", "chart"),
    ("avatar", "chart"),
    ("avatar", "mesh"),
)
#: The keys of a case mapping that hold a path, as key paths from the top: the material, the
#: body's files, a worn pattern's (``garment.pattern``: its file, or its body's files), and the
#: fabrics of a garment's bands, panels, layers and seams (``*``: every item of a list).
PATH_KEYS: tuple[tuple[str, ...], ...] = (
    ("material",),
    *(("body", *keys) for keys in BODY_PATH_KEYS),
    ("garment", "pattern", "file"),
    *(("garment", "pattern", "body", *keys) for keys in BODY_PATH_KEYS),
    ("garment", "bands", "*", "material"),
    ("garment", "panels", "*", "material"),
    ("garment", "layers", "*", "material"),
    ("garment", "seams", "material"),
)
#: Every item of a list, in a key path of `PATH_KEYS`.
EVERY = "*"


def bundled_material(value: str) -> bool:
    """Whether a case's ``material`` names a table in ``data/materials`` (no suffix: e.g.
    ``powernet``) rather than a file (`cloth.files.material.load_fabric`)."""
    return not Path(value).suffix


#: The shipped charts an avatar block may name by a word instead of a file.
CHART_NAMES = ("torso", "leg")


def is_path(keys: tuple[str, ...], value: str) -> bool:
    """Whether ``value`` at ``keys`` names a file: always, except a bundled material's name
    (the case's, or a band's, panel's, layer's or seam's) and a shipped chart's (``chart:
    leg``)."""
    if keys[-1] == "chart" and value in CHART_NAMES:
        return False
    return not (keys[-1] == "material" and bundled_material(value))


def _holders(data: Any, keys: tuple[str, ...]) -> list[dict[str, Any]]:
    """The mappings in ``data`` that hold the last key of ``keys`` (every item where a key is
    `EVERY`)."""
    holders = [data]
    for key in keys[:-1]:
        found = []
        for holder in holders:
            child = holder.get(key) if isinstance(holder, dict) else None
            if key == EVERY:
                found += (
                    [item for item in holder if isinstance(item, dict)]
                    if isinstance(holder, list)
                    else []
                )
            elif child is not None:
                found.append(child)
        holders = found
    return [h for h in holders if isinstance(h, dict)]


def relocated(data: dict[str, Any], source: str | Path, target: str | Path) -> dict[str, Any]:
    """A copy of the case mapping ``data`` whose relative paths, relative to folder ``source``,
    are rewritten relative to folder ``target`` (both taken from the working directory when
    relative). Absolute paths and bundled material names are kept as they are."""
    out = copy.deepcopy(data)
    source_dir = os.path.abspath(source)
    target_dir = os.path.abspath(target)
    for keys in PATH_KEYS:
        for holder in _holders(out, keys):
            value = holder.get(keys[-1])
            if not isinstance(value, str):
                continue
            if os.path.isabs(os.path.expanduser(value)) or not is_path(keys, value):
                continue
            holder[keys[-1]] = os.path.relpath(os.path.join(source_dir, value), target_dir)
    return out


__all__ = [
    "BODY_PATH_KEYS",
    "CHART_NAMES",
    "EVERY",
    "PATH_KEYS",
    "bundled_material",
    "is_path",
    "relocated",
]
