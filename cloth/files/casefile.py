"""Case files the tool writes (``cloth case write``, the pipeline's cases, a design's start
and designed cases): YAML, written atomically, their paths stored relative to the file's own
folder (`cloth.case.locations.relocated`), so that each runs as written from any directory."""

from __future__ import annotations

import logging
from pathlib import Path

import yaml

from cloth.case import Case
from cloth.case.locations import relocated
from cloth.io import atomic_output

log = logging.getLogger(__name__)


def write_case(case: Case | dict, path: str | Path, base_dir: str | Path = ".") -> Path:
    """Write ``case`` (a validated `Case`, or its mapping) to the YAML file ``path``, its
    relative paths, given relative to ``base_dir``, rewritten relative to ``path``'s folder."""
    path = Path(path)
    data = case.to_dict() if isinstance(case, Case) else case
    data = relocated(data, base_dir, path.parent)
    with atomic_output(path) as tmp:
        tmp.write_text(yaml.safe_dump(data, sort_keys=False))
    log.info("wrote %s", path)
    return path


__all__ = ["write_case"]
