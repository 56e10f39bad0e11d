"""Triangles to draw a result's body with: the body a state or result file records (its ``body``
attribute: the case's body block, its kind, and the resolved path and sha256 of any file it
reads), rebuilt for pictures only, cut to a band of heights.

Meshes are drawn as they are (never their fitted smooth surface, which only contact needs), the
parametric torso as its own mesh, closed-form bodies as rings of their sections. Nothing here
needs the case's base directory: the recorded path is absolute.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.analytic import Cone, Cylinder, EllipticCylinder
from cloth.bodies.leg import DEFAULT_LEG_CHART, leg_mesh, leg_of
from cloth.bodies.mesh import MeshBody
from cloth.bodies.torso import chart_size, torso_mesh
from cloth.io import sha256

if TYPE_CHECKING:
    import xarray as xr

log = logging.getLogger(__name__)

#: Rings of a closed-form body drawn over a band, and points per ring.
RINGS = 24
AROUND = 64
#: The parametric torso's drawing mesh: points around x rings over its whole height.
TORSO_AROUND, TORSO_RINGS = 96, 90

Triangles = tuple[NDArray[np.float64], NDArray[np.int64]]


def ring_triangles(rings: list[NDArray[np.float64]]) -> Triangles:
    """Vertices ((R k, 3), m) and faces ((2 (R - 1) k, 3)) of a tube through ``rings`` (each a
    (k, 3) closed loop of points, bottom to top)."""
    k = len(rings[0])
    i = np.arange(k)
    j = (i + 1) % k
    faces = [
        face
        for r in range(len(rings) - 1)
        for face in (
            np.stack([r * k + i, r * k + j, (r + 1) * k + i], axis=1),
            np.stack([r * k + j, (r + 1) * k + j, (r + 1) * k + i], axis=1),
        )
    ]
    return np.concatenate(rings), np.concatenate(faces).astype(np.int64)


def _section_rings(body, z_low: float, z_high: float) -> Triangles:
    lo, hi = body.z_range
    heights = np.linspace(max(lo, z_low), min(hi, z_high), RINGS)
    rings = []
    for z in heights:
        loop = body.sections(float(z))[0][:, 0]
        loop = loop[:: max(1, len(loop) // AROUND)]
        rings.append(np.column_stack([loop, np.full(len(loop), z)]))
    if len({len(r) for r in rings}) > 1:  # sections of differing sizes: resample to AROUND
        rings = [_resample(r, AROUND) for r in rings]
    return ring_triangles(rings)


def _resample(ring: NDArray[np.float64], count: int) -> NDArray[np.float64]:
    closed = np.vstack([ring, ring[:1]])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
    t = np.linspace(0.0, s[-1], count, endpoint=False)
    return np.column_stack([np.interp(t, s, closed[:, c]) for c in range(3)])


def crop(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    z_low: float,
    z_high: float,
    xy: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
):
    """Faces with every vertex between heights ``z_low`` and ``z_high`` (m) and, where ``xy``
    ((2,) low and high corners, m) is given, within that horizontal box; unused vertices
    dropped, faces renumbered."""
    corners = vertices[faces]
    keep = np.all((corners[:, :, 2] >= z_low) & (corners[:, :, 2] <= z_high), axis=1)
    if xy is not None:
        inside = (corners[:, :, :2] >= xy[0]) & (corners[:, :, :2] <= xy[1])
        keep &= np.all(inside, axis=(1, 2))
    faces = faces[keep]
    used, inverse = np.unique(faces, return_inverse=True)
    return vertices[used], inverse.reshape(faces.shape).astype(np.int64)


def body_triangles(record: dict | str, z_low: float, z_high: float) -> Triangles | None:
    """The body of ``record`` (a file's ``body`` attribute, dict or JSON) between heights
    ``z_low`` and ``z_high`` (m): vertices ((V, 3), m, z up) and faces ((F, 3)). None, logged,
    when the body's file has gone or changed since the run (the figure is drawn without it)."""
    if isinstance(record, str):
        record = json.loads(record)
    block = record["block"]
    path = record.get("path")
    if path is not None:
        if not Path(path).is_file():
            log.warning("%s: the body's file is gone; drawing without the body", path)
            return None
        if record.get("sha256") and sha256(path) != record["sha256"]:
            log.warning("%s: the body's file changed since the run; drawing without it", path)
            return None
    if "mesh" in block or "avatar" in block:  # an avatar's record has its mesh's path
        mesh = MeshBody.load(
            path,
            units=block.get("units", "m"),
            up=block.get("up", "z"),
            repair=bool(block.get("repair", False)),
            allow_holes=True,
        )
        return crop(mesh.vertices, mesh.faces, z_low, z_high)
    if "torso" in block:
        vertices, faces = torso_mesh(
            chart_size(block["torso"]["size"], path), TORSO_AROUND, TORSO_RINGS
        )
        return crop(vertices, faces, z_low, z_high)
    if "leg" in block:
        leg = block["leg"]
        chart = leg_of(leg, path or DEFAULT_LEG_CHART)
        vertices, faces = leg_mesh(chart, lean_deg=leg.get("lean_deg", 0.0))
        return crop(vertices, faces, z_low, z_high)
    kinds = {"cylinder": Cylinder, "elliptic_cylinder": EllipticCylinder, "cone": Cone}
    for key, kind in kinds.items():
        if key in block:
            return _section_rings(kind(**block[key]), z_low, z_high)
    raise ValueError(f"no drawable body in {block}")


#: The body is drawn this far (m) above and below the garment.
BODY_MARGIN = 0.08


def garment_positions(ds: xr.Dataset) -> NDArray[np.float64]:
    """Node positions of a result, (m, n, 3), m (rows bottom to top, columns around)."""
    return np.stack([ds[c].values for c in ("x", "y", "z")], axis=-1)


def body_band(ds: xr.Dataset) -> tuple[NDArray, NDArray] | None:
    """The result's body (vertices, faces) from below to above its garment and around it
    (`BODY_MARGIN`): a full body's arms beside the band are left out, so the garment, not the
    arm span, sets the frame."""
    if "body" not in ds.attrs:
        return None
    points = garment_positions(ds).reshape(-1, 3)
    low, high = points.min(axis=0) - BODY_MARGIN, points.max(axis=0) + BODY_MARGIN
    body = body_triangles(ds.attrs["body"], float(low[2]), float(high[2]))
    if body is None:
        return None
    return crop(*body, float(low[2]), float(high[2]), (low[:2], high[:2]))
