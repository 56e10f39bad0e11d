"""cloth: a spring-particle model of stretch fabric worn on a rigid body.

Implements and extends García, Ruiz, Gomez & Boulanger, *Spring-particle model for hyperelastic
cloth*: a grid of nodes joined by weft and warp springs whose force follows a piecewise-linear
stress-strain curve from a lab test.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("cloth")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
