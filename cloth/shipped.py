"""The data the package ships, found where the package is: the example fabrics, the size
charts, the avatars, the wearers of the default charts' sizes, the populations and the
measurement example (issue 70).

They live in the repository's top-level ``data/`` (its README there says what each file is,
with its licence and provenance); the wheel and the sdist map that folder into the package as
``cloth/data`` (``pyproject.toml``: ``package-dir``), so an installed package finds them through
`importlib.resources`, from any working folder, and a clone (an editable install) finds its own
``data/`` beside the package: one copy either way. The workflow (``workflow/``) and the example
configs (``config/``) are mapped in the same way, as ``cloth/workflow`` and ``cloth/config``.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def _folder(name: str) -> Path:
    """``cloth/NAME`` in an installed package, else the repository's top-level ``NAME/``."""
    packaged = files("cloth") / name
    if packaged.is_dir():
        return Path(str(packaged))
    return Path(__file__).resolve().parents[1] / name


def data_dir() -> Path:
    """The folder of the shipped data: ``cloth/data`` in an installed package, else the
    repository's ``data/`` beside the package."""
    return _folder("data")


def workflow_dir() -> Path:
    """The folder of the Snakemake workflow (its ``Snakefile``, rules, schemas): ``cloth/
    workflow`` in an installed package, else the repository's ``workflow/`` (`cloth pipeline`
    runs it; the repository's top-level Snakefile includes it)."""
    return _folder("workflow")


def shipped(*parts: str) -> Path:
    """The shipped file or folder at ``parts`` under `data_dir` (e.g. ``shipped("materials",
    "powernet.csv")``)."""
    return data_dir().joinpath(*parts)


__all__ = ["data_dir", "shipped", "workflow_dir"]
