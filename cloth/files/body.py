"""The body of a case's ``body`` block (docs/config.md)."""

from __future__ import annotations

from pathlib import Path

from cloth.bodies.analytic import Cone, Cylinder, EllipticCylinder
from cloth.bodies.base import Body
from cloth.bodies.leg import DEFAULT_LEG_CHART, SmoothLeg, leg_mesh, leg_of
from cloth.bodies.leg import POINTS as LEG_POINTS
from cloth.bodies.mesh import MeshBody
from cloth.bodies.surface import FitOptions
from cloth.bodies.torso import DEFAULT_CHART, SmoothTorso, chart_size, torso_mesh
from cloth.bodies.torso import LANDMARKS as TORSO_LANDMARKS
from cloth.errors import InputError
from cloth.files.avatar import avatar_mesh, load_mesh
from cloth.files.surface import smooth_body
from cloth.io import resolve, sha256
from cloth.paths import input_file, path_form


def body_from_config(
    block: dict,
    base_dir: str | Path = ".",
    span: tuple[float, float] | None = None,
    loop_point: tuple[float, float] | None = None,
) -> tuple[Body, dict]:
    """Build the body of a validated case's ``body`` block.

    Returns the body and its reference for state files: the block, plus the resolved path and
    sha256 of any file it reads. A mesh's smooth surface is fitted over its ``region``, else
    over ``span`` (the garment's bottom and top, m), else over the whole mesh, on the part
    around ``loop_point`` (the garment's, (x, y) m) where one is given; the reference records
    both. An ``avatar`` is the mesh it names (`cloth.files.avatar`), and a mesh
    with an avatar's sidecar takes its girth lines and the point inside the part a garment
    wraps from it.
    """
    ref: dict = {"block": block}
    if "avatar" in block:
        mesh_block = {k: v for k, v in block.items() if k != "avatar"}
        mesh_block["mesh"] = str(avatar_mesh(block["avatar"], base_dir))
        body, ref = body_from_config(mesh_block, base_dir, span, loop_point)
        ref["block"] = block
        return body, ref
    if "mesh" in block:
        path = input_file(block["mesh"], base_dir, None, "body.mesh", "mesh file")
        smooth = block.get("surface", "smooth") == "smooth"
        mesh, record = load_mesh(
            path,
            units=block.get("units", "m"),
            up=block.get("up", "z"),
            repair=bool(block.get("repair", False)),
            allow_holes=smooth,
        )
        ref.update(kind="mesh", path=str(path), sha256=sha256(path))
        if record is not None:
            ref["landmarks"] = {k: float(v) for k, v in record["landmarks"].items()}
            ref["avatar"] = {k: record.get(k) for k in ("model", "kind", "chart", "size")}
        if loop_point is not None:
            mesh.loop_point = (float(loop_point[0]), float(loop_point[1]))
            ref["loop_point"] = list(mesh.loop_point)
        body: Body = mesh
        if smooth:
            region = block.get("region") or span
            if region is not None:
                region = (float(region[0]), float(region[1]))
                ref["region"] = list(region)
            options = FitOptions(
                block.get("smoothing"),
                block.get("spacing"),
                block.get("refine"),
                block.get("denoise"),
                region,
            )
            surface_file = block.get("surface_file")
            if surface_file is not None:
                surface_file = resolve(
                    str(path_form(surface_file, None, "body.surface_file")), base_dir
                )
            body = smooth_body(mesh, options, surface_file)  # predeform records the fit
        else:
            ref["surface"] = {"kind": "mesh"}
    elif "torso" in block:
        spec = block["torso"]
        chart_path = DEFAULT_CHART
        if "chart" in spec:
            chart_path = input_file(spec["chart"], base_dir, None, "body.torso.chart", "size chart")
        chart = chart_size(spec["size"], chart_path)
        if spec.get("surface", "smooth") == "smooth":
            body = SmoothTorso(chart)
        else:
            vertices, faces = torso_mesh(chart, spec.get("around", 128), spec.get("rings", 120))
            body = MeshBody(vertices, faces, source=f"torso {spec['size']} ({chart_path})")
        ref.update(kind="torso", path=str(chart_path), sha256=sha256(chart_path))
        ref["landmarks"] = {k: chart.height[k] for k in TORSO_LANDMARKS}
    elif "leg" in block:
        spec = block["leg"]
        chart_path = DEFAULT_LEG_CHART
        if "chart" in spec:
            chart_path = input_file(spec["chart"], base_dir, None, "body.leg.chart", "leg chart")
        chart = leg_of(spec, chart_path)
        if spec.get("surface", "smooth") == "smooth":
            body = SmoothLeg(chart, float(spec.get("lean_deg", 0.0)))
        else:
            vertices, faces = leg_mesh(
                chart, spec.get("around", 96), spec.get("rings", 160), spec.get("lean_deg", 0.0)
            )
            body = MeshBody(vertices, faces, source=f"leg {chart.name} ({chart_path})")
        ref.update(kind="leg", path=str(chart_path), sha256=sha256(chart_path))
        ref["landmarks"] = {p: chart.height[p] for p in LEG_POINTS}
    elif "cylinder" in block:
        body = Cylinder(**block["cylinder"])
        ref["kind"] = "cylinder"
    elif "elliptic_cylinder" in block:
        body = EllipticCylinder(**block["elliptic_cylinder"])
        ref["kind"] = "elliptic_cylinder"
    elif "cone" in block:
        body = Cone(**block["cone"])
        ref["kind"] = "cone"
    else:
        raise InputError(
            "no body given; use one of mesh, avatar, torso, leg, cylinder, elliptic_cylinder, cone"
        )
    return body, ref


def body_from_record(record: dict, source: str | Path = "state file") -> Body:
    """The body of a state or result file's ``body`` record (`body_from_config`'s reference):
    its block with every file taken from the record's resolved path, checked against its
    sha256, and a mesh's smooth surface from the file the record names. A later stage needs no
    base directory; a body file that has gone or changed since predeform is refused in one line
    (from ``source``)."""
    block = dict(record["block"])
    path = record.get("path")
    if path is not None:
        if not Path(path).is_file():
            raise InputError(
                f"the body's file {path} is gone; restore it or rerun predeform", source, "body"
            )
        if record.get("sha256") and sha256(path) != record["sha256"]:
            raise InputError(
                f"the body's file {path} changed since predeform (its sha256 differs); rerun "
                "predeform",
                source,
                "body",
            )
        if "mesh" in block or "avatar" in block:
            block.pop("avatar", None)
            block["mesh"] = path
        elif "torso" in block:
            block["torso"] = {**block["torso"], "chart": path}
        elif "leg" in block:
            block["leg"] = {**block["leg"], "chart": path}
    surface = record.get("surface") or {}
    if "mesh" in block and surface.get("file"):
        block["surface_file"] = surface["file"]
    region, point = record.get("region"), record.get("loop_point")
    return body_from_config(
        block,
        span=None if region is None else tuple(region),
        loop_point=None if point is None else tuple(point),
    )[0]
