"""Avatar files: the mesh (PLY) and its sidecar (``.json``), and the avatars that ship.

`cloth body avatar` (`cloth.bodies.avatar.fit_avatar`) writes two files, each atomically:

- ``FILE.ply``: binary little-endian PLY, float32 vertices (m, z up, floor at 0, front +y)
  and triangle faces, written byte for byte the same for the same fit (no timestamp, no
  library banner), so that a regenerated avatar can be compared with ``cmp``;
- ``FILE.json``: its provenance: the model and its version, every parameter, the pose, the
  chart (its name, sha256 and size), each girth line's height, the chart's girth, the
  avatar's and the residual (m), the crop, and the point inside the part a garment wraps.

A mesh body whose file has such a sidecar takes its girth lines (the chart's heights) and that
point from it (`sidecar`), so an avatar is read as an avatar wherever it is given as a mesh.
The ``avatar: {chart, size}`` body block names one by its chart and size (`avatar_mesh`): the
file ``avatar.mesh`` gives, else the avatar of the default charts that ships in
``data/bodies/avatars/`` and whose sidecar holds the chart's sha256 and the size.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.avatar import ARM_RAISE_DEG, CROP_MARGIN, LEG_SPREAD_DEG, MODEL, crop
from cloth.bodies.leg import DEFAULT_LEG_CHART
from cloth.bodies.mesh import MeshBody
from cloth.bodies.torso import DEFAULT_CHART
from cloth.errors import InputError
from cloth.io import atomic_output, sha256
from cloth.paths import input_file
from cloth.shipped import data_dir

#: The shipped charts an avatar block may name instead of a file (``chart: leg``).
SHIPPED_CHARTS = {"torso": DEFAULT_CHART, "leg": DEFAULT_LEG_CHART}
#: Where the default charts' avatars ship.
SHIPPED = data_dir() / "bodies" / "avatars"
#: The sidecar's format (its ``cloth_avatar`` key).
FORMAT = 1
LICENCES = "Anny: Apache-2.0 (NAVER Corp.); MakeHuman assets: CC0"


def sidecar_path(mesh: str | Path) -> Path:
    return Path(mesh).with_suffix(".json")


def write_ply(vertices: NDArray, faces: NDArray, path: str | Path) -> Path:
    """``vertices`` ((V, 3), m, as float32) and ``faces`` ((F, 3) int) to a binary PLY,
    atomically; the same arrays give the same bytes."""
    vertices = np.ascontiguousarray(vertices, dtype="<f4")
    faces = np.asarray(faces, dtype="<i4")
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment cloth avatar (metres, z up)\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    records = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    records["n"] = 3
    records["v"] = faces
    with atomic_output(path) as tmp:
        tmp.write_bytes(header.encode("ascii") + vertices.tobytes() + records.tobytes())
    return Path(path)


def avatar_output(output: str | Path) -> Path:
    """``output`` as an avatar's mesh file: a ``.ply`` (one line otherwise)."""
    output = Path(output)
    if output.suffix.lower() != ".ply":
        raise InputError("an avatar is written as PLY; name the output FILE.ply", output, "-o")
    return output


def write_avatar(
    avatar, chart: str | Path, output: str | Path, full: bool = False
) -> tuple[Path, Path]:
    """The cropped mesh of ``avatar`` (`cloth.bodies.avatar.Avatar`; ``full``: the whole
    body, uncropped) to ``output`` (a .ply) and its sidecar beside it; both atomic, the
    sidecar last (a mesh without one is not taken for an avatar)."""
    output = avatar_output(output)
    vertices, faces = (avatar.vertices, avatar.faces) if full else crop(avatar)
    targets = avatar.targets
    residuals = avatar.residuals()
    record = {
        "cloth_avatar": FORMAT,
        "model": MODEL,
        "versions": avatar.versions,
        "licences": LICENCES,
        "kind": targets.kind,
        "chart": Path(chart).name,
        "chart_sha256": sha256(chart),
        "size": targets.size,
        "pose": (
            {"arm_raise_deg": ARM_RAISE_DEG, "leg_spread_deg": LEG_SPREAD_DEG}
            if avatar.posed
            else "the model's A-pose"
        ),
        "parameters": {k: round(v, 12) for k, v in avatar.parameters.items()},
        "stature_m": {
            "chart": targets.stature,
            "avatar": round(avatar.stature, 9),
            "residual": round(residuals["stature"], 9),
        },
        "girths_m": {
            name: {
                "height": targets.height[name],
                "chart": None if name in targets.free else targets.girth[name],
                "avatar": round(avatar.girth[name], 9),
                "residual": round(residuals[name], 9) if name in residuals else None,
            }
            for name in targets.girth
        },
        "landmarks": dict(targets.height),
        "loop_point_m": [round(c, 9) for c in avatar.loop_point],
        "crop_m": None
        if full
        else [max(targets.span[0] - CROP_MARGIN, 0.0), targets.span[1] + CROP_MARGIN],
        "evaluations": avatar.evaluations,
    }
    write_ply(vertices, faces, output)
    side = sidecar_path(output)
    with atomic_output(side) as tmp:
        tmp.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
    return output, side


def sidecar(mesh: str | Path) -> dict | None:
    """The avatar sidecar of a mesh file, or None where it has none; one line for a sidecar
    that is not an avatar's or lacks its girth lines."""
    side = sidecar_path(mesh)
    if not side.is_file():
        return None
    try:
        record = json.loads(side.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"the avatar's sidecar is not JSON ({exc})", side) from None
    if not isinstance(record, dict) or "cloth_avatar" not in record:
        return None
    for key in ("landmarks", "loop_point_m", "size", "kind"):
        if key not in record:
            raise InputError(
                f"the avatar's sidecar has no {key}; write it anew with cloth body avatar",
                side,
                key,
            )
    return record


def load_mesh(
    path: str | Path,
    units: str = "m",
    up: str = "z",
    repair: bool = False,
    allow_holes: bool = False,
) -> tuple[MeshBody, dict | None]:
    """`cloth.bodies.mesh.MeshBody.load` of ``path``, with the ``loop_point`` of its avatar
    sidecar where it has one (`sidecar`, also returned): every stage, the fit and the check
    see one body, so they share one fitted surface."""
    mesh = MeshBody.load(path, units=units, up=up, repair=repair, allow_holes=allow_holes)
    record = sidecar(path)
    if record is not None:
        mesh.loop_point = (float(record["loop_point_m"][0]), float(record["loop_point_m"][1]))
    return mesh, record


def shipped(chart: str | Path, size: str) -> Path | None:
    """The shipped avatar of ``size`` of ``chart`` (by the chart's sha256), or None."""
    digest = sha256(chart)
    for side in sorted(SHIPPED.glob("*.json")):
        record = json.loads(side.read_text())
        if record.get("chart_sha256") == digest and record.get("size") == size:
            return side.with_suffix(".ply")
    return None


def avatar_mesh(spec: dict, base_dir: str | Path = ".") -> Path:
    """The mesh file of an ``avatar`` body block (module docstring): ``mesh`` where given,
    else the shipped avatar of ``chart`` (default the torso chart) and ``size``; one line
    saying how to make one where none ships."""
    if "mesh" in spec:
        path = input_file(spec["mesh"], base_dir, None, "body.avatar.mesh", "avatar mesh")
        if sidecar(path) is None:
            raise InputError(
                "this mesh has no avatar sidecar (FILE.json); write it with cloth body avatar, "
                "or give it as body.mesh",
                path,
                "body.avatar.mesh",
            )
        return path
    chart = DEFAULT_CHART
    if spec.get("chart") in SHIPPED_CHARTS:  # a shipped chart by name, from any folder
        chart = SHIPPED_CHARTS[spec["chart"]]
    elif "chart" in spec:
        chart = input_file(spec["chart"], base_dir, None, "body.avatar.chart", "size chart")
    found = shipped(chart, spec["size"])
    if found is None:
        raise InputError(
            f"no avatar of size {spec['size']} ships for this chart; make one with `cloth body "
            f"avatar {chart} --size {spec['size']} -o FILE.ply` (pip install 'cloth[bodies]') "
            "and give it as avatar.mesh",
            chart,
            "body.avatar",
        )
    return found
