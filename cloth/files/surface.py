"""The fitted-surface file (``surface.nc``) and the cache that keeps one per mesh and options.

A fit (`cloth.bodies.surface`) takes seconds on a scan; predeform, relax and aggregate all need
it, so it is fitted once and kept: in the file the case's ``surface_file`` names (the
pipeline's ``cloth.pipeline.plan.body_file("surface.nc")``, made by rule ``body_surface``), else
in the cache folder (`cache_dir`) under its key, the sha256 of the mesh as used (metres, z up)
and the options. A file whose key differs from the mesh's is not used: the surface is fitted
anew.

Variables (CF-1.11): ``coefficient`` (x, y, z), m: the cubic B-spline coefficients (the smoothed
signed distance, positive outside), zlib-compressed; coordinates ``x``, ``y``, ``z`` (m) at the
coefficients' positions (float32, the precision the fit rounds to). Attributes: ``cloth_kind =
"surface"``, the key, sigma, h, the trusted band and clamp, the crease spacing and the vertices'
deviation (m), the mesh's source.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.bodies.mesh import MeshBody
from cloth.bodies.smoothmesh import SmoothMeshBody
from cloth.bodies.spline import SplineField
from cloth.bodies.surface import (
    DEFAULT_OPTIONS,
    FitOptions,
    SurfaceFit,
    fit_surface,
    mesh_key,
)
from cloth.io import global_attrs, read_netcdf, write_netcdf

log = logging.getLogger(__name__)

_LENGTHS = (
    "smoothing",
    "spacing",
    "trusted",
    "clamp",
    "crease_spacing",
    "deviation_max",
    "deviation_rms",
    "deviation_mean",
)


def write_surface(fit: SurfaceFit, path: str | Path, source: str = "") -> Path:
    """Write ``fit`` to ``path`` atomically."""
    spline = fit.field
    coords = {
        axis: (
            (axis,),
            spline.origin[a] + spline.spacing * np.arange(spline.coefficients.shape[a]),
            {"units": "m", "long_name": f"{axis} of the spline coefficients (body frame, z up)"},
        )
        for a, axis in enumerate("xyz")
    }
    ds = xr.Dataset(
        {
            "coefficient": (
                ("x", "y", "z"),
                spline.coefficients.astype(np.float32),  # the fit's own precision
                {
                    "units": "m",
                    "long_name": "cubic B-spline coefficients of the smoothed signed distance "
                    "to the body (positive outside)",
                },
            )
        },
        coords=coords,
    )
    ds.attrs.update(global_attrs("cloth smooth body surface"))
    ds.attrs.update(
        cloth_kind="surface",
        key=fit.key,
        mesh_source=source,
        refine_levels=int(fit.refine_levels),
        denoise_move_m=float(fit.denoise_move),
        **{f"{name}_m": float(getattr(fit, name)) for name in _LENGTHS},
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_netcdf(ds, path, compress=("coefficient",))


def read_surface(path: str | Path) -> SurfaceFit:
    ds = read_netcdf(path, "surface", ("coefficient",))
    x, y, z = (ds[a].values for a in "xyz")
    spline = SplineField(
        np.array([x[0], y[0], z[0]]),
        float(ds.attrs["spacing_m"]),
        ds["coefficient"].values.astype(np.float64),
    )
    return SurfaceFit(
        field=spline,
        key=str(ds.attrs["key"]),
        refine_levels=int(ds.attrs.get("refine_levels", 0)),
        denoise_move=float(ds.attrs.get("denoise_move_m", 0.0)),
        **{name: float(ds.attrs[f"{name}_m"]) for name in _LENGTHS},
    )


def cache_dir() -> Path:
    """Where fitted surfaces are kept when the case names no ``surface_file``:
    ``$CLOTH_CACHE_DIR``, else ``$XDG_CACHE_HOME/cloth`` (``~/.cache/cloth``), + ``surfaces``."""
    root = os.environ.get("CLOTH_CACHE_DIR")
    if not root:
        xdg = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        root = str(Path(xdg) / "cloth")
    return Path(root) / "surfaces"


def smooth_body(
    mesh: MeshBody,
    options: FitOptions = DEFAULT_OPTIONS,
    path: str | Path | None = None,
    progress: bool | None = None,
) -> SmoothMeshBody:
    """The smooth body of ``mesh``; its surface, at the first query, is read from ``path``
    (default: the cache, keyed by `mesh_key`) when that holds this mesh's fit with these
    options, else fitted and written there (`load_or_fit`)."""
    return SmoothMeshBody(mesh, lambda: load_or_fit(mesh, options, path, progress), options.denoise)


def load_or_fit(
    mesh: MeshBody,
    options: FitOptions = DEFAULT_OPTIONS,
    path: str | Path | None = None,
    progress: bool | None = None,
) -> tuple[SurfaceFit, Path]:
    """The fit of ``mesh`` with ``options`` and the file that keeps it (`smooth_body`): read
    from ``path`` or the cache, whichever holds it, else fitted into ``path`` (or the cache
    when ``path`` holds another mesh's fit, or is not given)."""
    key = mesh_key(mesh, options)
    cached = cache_dir() / f"{key[:32]}.nc"
    places = [Path(path), cached] if path is not None else [cached]
    for place in places:
        if place.is_file():
            fit = read_surface(place)
            if fit.key == key:
                log.info("smooth surface from %s", place)
                return fit, place
            log.warning("%s holds the surface of another mesh or other options", place)
    target = places[0] if not places[0].is_file() else cached  # never overwrite another's fit
    fit = fit_surface(mesh, options, progress)
    write_surface(fit, target, mesh.source)
    log.info("wrote %s", target)
    return fit, target
