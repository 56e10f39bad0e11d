"""Mesh and table export of a result: PLY (vertex colours and fields), VTU, CSV of nodes."""

from __future__ import annotations

import csv
import io as _io
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.errors import InputError
from cloth.io import atomic_output

FIELDS = (
    "stress_weft",
    "stress_warp",
    "strain_weft",
    "strain_warp",
    "tension_weft",
    "tension_warp",
    "pressure",
    "contact",
)


def _faces(n: int, m: int, closed: bool) -> np.ndarray:
    """Two triangles per grid cell, in the grid's node order."""
    cols = n if closed else n - 1
    j, i = np.meshgrid(np.arange(m - 1), np.arange(cols), indexing="ij")
    a, b = j * n + i, j * n + (i + 1) % n
    c, d = (j + 1) * n + i, (j + 1) * n + (i + 1) % n
    return np.concatenate(
        [np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)]
    )


def export(ds: xr.Dataset, path: str | Path, field: str = "stress_weft") -> Path:
    """Write ``ds`` to ``path`` by its suffix: .ply, .vtu (meshio) or .csv."""
    import trimesh
    from matplotlib import colormaps

    path = Path(path)
    n, m, closed = int(ds.attrs["n"]), int(ds.attrs["m"]), bool(int(ds.attrs["closed"]))
    x = np.stack([ds[c].values.ravel() for c in ("x", "y", "z")], axis=1)
    values = {name: ds[name].values.ravel() for name in FIELDS if name in ds}
    suffix = path.suffix.lower()
    if suffix == ".csv":
        buffer = _io.StringIO()
        writer = csv.writer(buffer)
        names = list(values)
        writer.writerow(
            ["row", "col", "x_m", "y_m", "z_m", *(f"{k}_{ds[k].attrs['units']}" for k in names)]
        )
        for k in range(n * m):
            writer.writerow(
                [
                    k // n,
                    k % n,
                    *(f"{v:.9g}" for v in x[k]),
                    *(f"{values[nm][k]:.9g}" for nm in names),
                ]
            )
        with atomic_output(path) as tmp:
            tmp.write_text(buffer.getvalue())
        return path
    faces = _faces(n, m, closed)
    if suffix == ".ply":
        if field not in values:
            raise InputError(
                f"unknown field {field!r}; use one of {', '.join(values)}", field="--field"
            )
        data = values[field]
        span = np.nanmax(data) - np.nanmin(data)
        scaled = (data - np.nanmin(data)) / (span if span > 0 else 1.0)
        colours = (colormaps["viridis"](np.nan_to_num(scaled)) * 255).astype(np.uint8)
        mesh = trimesh.Trimesh(x, faces, vertex_colors=colours, process=False)
        for name, array in values.items():
            mesh.vertex_attributes[name] = np.asarray(array, dtype=np.float64)
        with atomic_output(path) as tmp:
            mesh.export(tmp, file_type="ply")
        return path
    if suffix == ".vtu":
        try:
            import meshio
        except ImportError:
            raise InputError(
                "VTU export needs meshio: pip install 'cloth[export]'", field="-o"
            ) from None
        with atomic_output(path) as tmp:
            meshio.write(
                tmp, meshio.Mesh(x, [("triangle", faces)], point_data=values), file_format="vtu"
            )
        return path
    raise InputError(f"unknown export format {suffix!r}; use .ply, .vtu or .csv", field="-o")
