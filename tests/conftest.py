"""Shared fixtures: an example fabric with distinctly different weft and warp curves."""

from __future__ import annotations

import matplotlib
import pytest

matplotlib.use("Agg")

from cloth.materials import Fabric, StressStrainCurve


def make_fabric(thickness: float = 5.0e-4) -> Fabric:
    """A J-shaped elastane-knit-like fabric: weft softer than warp (numbers illustrative)."""
    weft = StressStrainCurve([0.0, 0.1, 0.3, 0.6, 1.0], [0.0, 0.05e6, 0.2e6, 0.6e6, 1.6e6])
    warp = StressStrainCurve([0.0, 0.15, 0.4, 0.8], [0.0, 0.12e6, 0.5e6, 1.8e6])
    return Fabric("test knit", weft=weft, warp=warp, thickness=thickness)


def write_obj(path, vertices, faces):
    """Write a mesh as OBJ at full float64 precision (STL and trimesh's PLY store float32)."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def fabric() -> Fabric:
    return make_fabric()


@pytest.fixture(autouse=True, scope="session")
def _surface_cache(tmp_path_factory):
    """Fitted mesh surfaces go to a folder of the test session, not the user's cache."""
    import os

    os.environ["CLOTH_CACHE_DIR"] = str(tmp_path_factory.mktemp("cache"))
