"""cloth: a spring-particle model of stretch fabric worn on a rigid body.

Implements and extends García, Ruiz, Gomez & Boulanger, *Spring-particle model for hyperelastic
cloth*: a grid of nodes joined by weft and warp springs whose force follows a piecewise-linear
stress-strain curve from a lab test.

The front door (issue 70; docs/how-to/python.md): `Case` (``Case.load(path)``,
``Case.of(mapping)``), `run`, `design`, `sizes`, `compare`, `calibrate`, `material`, `body`,
and `InputError`, the one error type of bad input, with the command's one-line message. Each
is the code its command calls (`cloth.api`). They are loaded when first used, so that
``import cloth`` and ``cloth --version`` stay light.

Examples
--------
>>> import cloth
>>> fabric = cloth.material("powernet")
>>> fabric.name
'power net 80/20 (illustrative)'
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version
from typing import Any

from cloth.errors import InputError

try:
    __version__ = version("cloth")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

#: The front door's names and the module each is loaded from on first use.
_FRONT = {
    "Case": "cloth.case",
    "Run": "cloth.api",
    "run": "cloth.api",
    "design": "cloth.api",
    "sizes": "cloth.api",
    "compare": "cloth.api",
    "calibrate": "cloth.api",
    "material": "cloth.api",
    "body": "cloth.api",
}


def __getattr__(name: str) -> Any:
    """A front-door name, loaded with its module on first use (PEP 562)."""
    if name in _FRONT:
        value = getattr(import_module(_FRONT[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'cloth' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_FRONT])


__all__ = [
    "Case",
    "InputError",
    "Run",
    "__version__",
    "body",
    "calibrate",
    "compare",
    "design",
    "material",
    "run",
    "sizes",
]
