"""The smooth contact surface of a mesh body: a smoothed signed distance as a cubic B-spline.

Contact with a triangle mesh itself has two faults (docs/bodies.md): a node pressed onto a
convex edge is balanced without being at an energy minimum, so Newton stalls, and by Laplace's
law a polyhedron puts no pressure on its flat facets and all of it on their edges. Every mesh
body is therefore contacted, by default, through a C2 surface fitted to it once:

1. **Signed distance on a grid.** Samples at spacing h over the mesh's box (plus a margin):
   the exact distance to the triangles (libigl's AABB tree) with the sign of the generalised
   winding number (inside where it exceeds 1/2; libigl's fast winding number), so a few small
   holes do not flip it. Only samples within the band where the result is used are computed
   exactly: a coarse grid (spacing `COARSE` h) bounds the rest, whose value is the clamp
   +-c, c = t + `TRUNCATE` sigma + h, with t = sigma + 2 h the trusted band (below).
2. **Gaussian smoothing** of width sigma (``smoothing``): the field no longer has the mesh's
   creases (unsmoothed, they stay as ridges of radius ~h whose curvature stalls Newton).
3. **A tensor-product cubic B-spline whose coefficients are the smoothed samples.** Not an
   interpolating spline: an interpolating prefilter rings at convex creases and invents
   concavities; with the samples as coefficients the spline reproduces linear fields exactly
   and keeps the sign of the curvature. It is C2: value, gradient and Hessian are exact and
   continuous, so Newton gets the curvature term it gets on the closed-form bodies.

The surface is the zero level set phi = 0; closest points, normals and the distance Hessian
come from `cloth.bodies.implicit.ImplicitBody`. phi is trusted where the Gaussian window did
not reach the clamp: inside the grid and |phi| < t. A point outside that band (a line-search
trial far off) starts its closest-point Newton from its closest point on the mesh, which lies
within about a millimetre of the surface, and takes its side from the winding number.

Defaults (docs/bodies.md): sigma = `SMOOTHING_FACTOR` x the mesh's crease spacing, within
[`SMOOTHING_FLOOR`, `SMOOTHING_CAP`]; the crease spacing is the median width of the facets
across their edges, weighted by the edges' bending angle (a fine scan: the floor; a coarse
mesh: enough to round its facets, whose creases would otherwise modulate the curvature; a box's
flat sides: the cap). h = min(`MAX_SPACING`, `SPACING_FACTOR` sigma): sampled coarser than
sigma / 2.5, the mesh's creases alias into the smoothed field (measured on a 128-gon cylinder:
hoop curvature +-1.2 % at sigma / h = 1.3, +-0.3 % at 2, +-0.2 % at 3).

Smoothing moves the surface: by about sigma^2 x the mean curvature
inward on convex parts. `fit_surface` measures it at the mesh's vertices (`SurfaceFit.deviation`)
and every state and result file records sigma, h and that deviation.

Shapes and units: points (P, 3) m; the coefficient grid (nx, ny, nz) m at nodes
``origin + spacing * (i, j, k)``; values m; gradients 1; Hessians 1/m.
"""

from __future__ import annotations

import hashlib
import json
import logging
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import denoise, refine
from cloth.bodies.base import hull_polygon
from cloth.bodies.mesh import MeshBody
from cloth.bodies.sections import follow, loop_area, loop_around
from cloth.bodies.spline import SplineField
from cloth.bodies.tessellation import FEATURE_ANGLE, crease_spacing
from cloth.errors import InputError
from cloth.progress import progress as progress_of

log = logging.getLogger(__name__)

#: Smallest and largest default smoothing width sigma, m.
SMOOTHING_FLOOR = 5e-3
SMOOTHING_CAP = 15e-3
#: Default sigma as a multiple of the mesh's crease spacing.
SMOOTHING_FACTOR = 1.0
#: Largest default grid spacing h, m, and h as a fraction of sigma.
MAX_SPACING = 3e-3
SPACING_FACTOR = 0.4
#: Gaussian kernel radius, in sigma.
TRUNCATE = 3.0
#: The coarse grid that bounds the distance is this many fine cells apart.
COARSE = 4
#: Largest grid (samples) fitted: about 5 arrays of 8 bytes each per sample at the peak.
MAX_SAMPLES = 80_000_000
#: Exact distance samples per call to libigl (and progress-bar update).
SAMPLE_BATCH = 655_360
#: Format version of the fit: part of the cache key, so a change refits.
FIT_VERSION = 4
#: Most levels of refinement a case may ask for (each multiplies the faces by 4).
REFINE_LIMIT = 5
#: A region (`FitOptions.region`) is widened by this much (m) above, below and around the
#: part it covers, before the fit's own margin.
REGION_MARGIN = 0.03
#: Heights (m) apart at which a region's sections are followed (`region_box`).
REGION_STEP = 0.005


@dataclass(frozen=True)
class FitOptions:
    """How a mesh's smooth surface is fitted (the ``body`` block's ``smoothing`` and
    ``spacing``, m, ``refine``, the levels of curved refinement of `cloth.bodies.refine`,
    ``denoise``, whether the vertices are filtered along their normals first,
    `cloth.bodies.denoise`, and ``region``, the heights (bottom, top), m, a garment spans, to
    which the fit is confined (`region_box`); None: the defaults of the module docstring, and
    the whole mesh)."""

    smoothing: float | None = None
    spacing: float | None = None
    refine: int | None = None
    denoise: bool | None = None
    region: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for name in ("smoothing", "spacing"):
            value = getattr(self, name)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise InputError(
                    f"{name} must be a positive length in m, got {value}", field=f"body.{name}"
                )
        if self.refine is not None and not (
            isinstance(self.refine, int | np.integer) and 0 <= self.refine <= REFINE_LIMIT
        ):
            raise InputError(
                f"refine must be a whole number of levels from 0 to {REFINE_LIMIT}, got "
                f"{self.refine!r}",
                field="body.refine",
            )
        if self.denoise is not None and not isinstance(self.denoise, bool | np.bool_):
            raise InputError(
                f"denoise must be true or false, got {self.denoise!r}", field="body.denoise"
            )
        if self.region is not None and not (
            len(self.region) == 2
            and all(np.isfinite(self.region))
            and self.region[0] < self.region[1]
        ):
            raise InputError(
                f"region must be two heights [bottom, top] in m, bottom below top, got "
                f"{list(self.region)!r}",
                field="body.region",
            )


DEFAULT_OPTIONS = FitOptions()


@dataclass(frozen=True)
class SurfaceFit:
    """A fitted surface: the field and how it was made.

    Attributes
    ----------
    field : SplineField
    smoothing, spacing, trusted, clamp : float, m
        sigma, h, the band |phi| < trusted where phi is exact, the clamp value.
    crease_spacing : float, m
        The facet width across the creases of the mesh as fitted, after refinement (what the
        default sigma follows).
    refine_levels : int
        Times each triangle was split, with its new points on curved patches, before the fit
        (`cloth.bodies.refine`).
    denoise_move : float, m
        RMS move of the vertices by the noise filter before the fit (`cloth.bodies.denoise`;
        0: not filtered).
    deviation_max, deviation_rms : float, m
        Distance of the mesh's vertices from the fitted surface (largest, root mean square).
    deviation_mean : float, m
        Mean signed distance of the vertices from the surface (positive: the surface lies
        inside the mesh).
    key : str
        sha256 of the mesh (metres, z up) and the options: the cache key.
    """

    field: SplineField
    smoothing: float
    spacing: float
    trusted: float
    clamp: float
    crease_spacing: float
    deviation_max: float
    deviation_rms: float
    deviation_mean: float
    key: str
    refine_levels: int = 0
    denoise_move: float = 0.0

    def record(self) -> dict[str, float | str]:
        """What state and result files record of the fit (lengths in m)."""
        return {
            "smoothing_m": self.smoothing,
            "spacing_m": self.spacing,
            "crease_spacing_m": self.crease_spacing,
            "refine_levels": self.refine_levels,
            "denoise_move_m": self.denoise_move,
            "deviation_max_m": self.deviation_max,
            "deviation_rms_m": self.deviation_rms,
            "deviation_mean_m": self.deviation_mean,
            "key": self.key,
        }


def mesh_key(mesh: MeshBody, options: FitOptions) -> str:
    """sha256 of the mesh as used (metres, z up), the fit options and the defaults."""
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(mesh.vertices).tobytes())
    digest.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
    digest.update(
        json.dumps(
            {
                "smoothing": options.smoothing,
                "spacing": options.spacing,
                "refine": options.refine,
                "denoise": options.denoise,
                "region": None if options.region is None else list(options.region),
                "loop_point": None if mesh.loop_point is None else list(mesh.loop_point),
                "region_margin": REGION_MARGIN,
                "version": FIT_VERSION,
                "defaults": [
                    SMOOTHING_FLOOR,
                    SMOOTHING_CAP,
                    SMOOTHING_FACTOR,
                    MAX_SPACING,
                    SPACING_FACTOR,
                    TRUNCATE,
                    COARSE,
                    FEATURE_ANGLE,
                    refine.ALPHA,
                    refine.TARGET_SPACING,
                    refine.MAX_LEVELS,
                    refine.NOISE_RATIO,
                    denoise.STRENGTH,
                ],
            }
        ).encode()
    )
    return digest.hexdigest()


def region_box(
    mesh: MeshBody, region: tuple[float, float]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The box ((3,), (3,), m) of the part of ``mesh`` a garment between the heights ``region``
    wraps, widened by `REGION_MARGIN`: its sections every `REGION_STEP`, followed from the
    middle height (`cloth.bodies.sections.follow`) from the loops around the mesh's
    ``loop_point``, else the largest (the torso of a full-body scan, not its arms; one leg).
    Logged: a full-body scan is fitted there only."""
    z_low, z_high = mesh.z_range
    # strictly inside: a cropped mesh's flat cap is a degenerate section
    inset = 1e-3 * REGION_STEP
    bottom = max(region[0] - REGION_MARGIN, z_low + inset)
    top = min(region[1] + REGION_MARGIN, z_high - inset)
    count = max(2, int(np.ceil((top - bottom) / REGION_STEP)) + 1)
    heights = np.linspace(bottom, top, count)
    # a height may still miss the mesh (a region beside it): keep the rows that cut it
    sections = []
    kept = []
    for z in heights:
        try:
            loops = mesh.sections(float(z))
        except InputError:
            continue
        sections.append(loops)
        kept.append(z)
    if not sections:
        raise InputError(
            f"the mesh has no section between {bottom:.4g} and {top:.4g} m; give body.region "
            "within the body",
            mesh.source or None,
            "body.region",
        )
    start = len(sections) // 2
    if mesh.loop_point is not None:
        first = loop_around(sections[start], mesh.loop_point)
    else:
        first = [max(sections[start], key=loop_area)]
    parts = follow(sections, start, first)
    points = np.concatenate([hull_polygon(loops) for loops in parts])
    low = np.array([*(points.min(axis=0) - REGION_MARGIN), kept[0] - REGION_MARGIN])
    high = np.array([*(points.max(axis=0) + REGION_MARGIN), kept[-1] + REGION_MARGIN])
    log.info(
        "fitting the smooth surface over the part a garment at %.4g-%.4g m wraps: x %.3g-%.3g, "
        "y %.3g-%.3g, z %.3g-%.3g m (body.region sets the heights; the mesh spans %.3g-%.3g m)",
        region[0],
        region[1],
        low[0],
        high[0],
        low[1],
        high[1],
        low[2],
        high[2],
        z_low,
        z_high,
    )
    return low, high


def _signed_distance(vertices: NDArray, faces: NDArray, points: NDArray) -> NDArray:
    """Exact distance to the triangles, negative where the winding number exceeds 1/2."""
    import igl

    squared, _, _ = igl.point_mesh_squared_distance(points, vertices, faces)
    winding = igl.fast_winding_number(vertices, faces, points)
    return np.where(winding > 0.5, -1.0, 1.0) * np.sqrt(squared)


def fit_surface(
    mesh: MeshBody, options: FitOptions = DEFAULT_OPTIONS, progress: bool | None = None
) -> SurfaceFit:
    """Fit the smooth surface of ``mesh`` (module docstring); progress over the exact
    distance samples (``progress``: None = a bar on a terminal, else log lines)."""
    from scipy.ndimage import gaussian_filter, laplace

    vertices, faces = mesh.vertices, mesh.faces
    vertices, move = denoise.as_fitted(vertices, faces, options.denoise, refine.NOISE_RATIO)
    creases = crease_spacing(vertices, faces)
    levels = options.refine
    if levels is None:
        levels = refine.auto_levels(vertices, faces, creases)
    if levels:
        vertices, faces = refine.phong_refine(vertices, faces, levels)
        log.info("refined the mesh %d times along curved patches: %d faces", levels, len(faces))
        creases = crease_spacing(vertices, faces)
    sigma = options.smoothing or float(
        np.clip(SMOOTHING_FACTOR * creases, SMOOTHING_FLOOR, SMOOTHING_CAP)
    )
    h = options.spacing or min(MAX_SPACING, SPACING_FACTOR * sigma)
    if h > sigma:
        raise InputError(
            f"spacing {h:.4g} m is coarser than the smoothing {sigma:.4g} m, so the grid "
            "would alias the surface; set spacing at most smoothing (default: half of it)",
            mesh.source or None,
            "body.spacing",
        )
    trusted = sigma + 2 * h
    clamp = trusted + TRUNCATE * sigma + 4 * h
    low = vertices.min(axis=0) - clamp - 3 * h
    high = vertices.max(axis=0) + clamp + 3 * h
    if options.region is not None:
        part_low, part_high = region_box(mesh, options.region)
        low = np.maximum(low, part_low - clamp - 3 * h)
        high = np.minimum(high, part_high + clamp + 3 * h)
    coarse_shape = np.ceil((high - low) / (COARSE * h)).astype(int) + 1
    shape = (coarse_shape - 1) * COARSE + 1
    samples = int(np.prod(shape))
    if samples > MAX_SAMPLES:
        raise InputError(
            f"the smooth surface needs {samples:,} grid samples at spacing {h * 1e3:.3g} mm "
            f"(at most {MAX_SAMPLES:,}, about {MAX_SAMPLES * 40 / 2**30:.0f} GiB); set a larger "
            "spacing (and smoothing), or give body.region, the heights [bottom, top] a garment "
            "spans (cloth body fit --region)",
            mesh.source or None,
            "body.spacing",
        )
    log.info(
        "fitting the smooth surface of %s: sigma %.3g mm, h %.3g mm (creases %.3g mm apart), "
        "grid %d x %d x %d",
        mesh.source or "the mesh",
        sigma * 1e3,
        h * 1e3,
        creases * 1e3,
        *shape,
    )
    # coarse samples bound the distance: |d(x)| >= |d(c)| - |x - c| (1-Lipschitz)
    axes = [low[a] + COARSE * h * np.arange(coarse_shape[a]) for a in range(3)]
    coarse_points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    coarse = _signed_distance(vertices, faces, coarse_points).reshape(tuple(coarse_shape))
    far_coarse = np.abs(coarse) - 0.5 * np.sqrt(3) * COARSE * h > clamp
    nearest = [np.rint(np.arange(n) / COARSE).astype(np.intp) for n in shape]
    index = np.ix_(*nearest)
    values = np.where(far_coarse[index], np.sign(coarse)[index] * clamp, np.nan)
    exact = np.flatnonzero(np.isnan(values))
    flat = values.reshape(-1)
    with progress_of(total=exact.size, desc="surface fit", unit="sample", show=progress) as bar:
        for start in range(0, exact.size, SAMPLE_BATCH):
            chunk = exact[start : start + SAMPLE_BATCH]
            ijk = np.stack(np.unravel_index(chunk, tuple(shape)), axis=1)
            flat[chunk] = _signed_distance(vertices, faces, low + h * ijk)
            bar.update(chunk.size)
    np.clip(values, -clamp, clamp, out=values)
    smoothed = gaussian_filter(values, sigma / h, mode="nearest", truncate=TRUNCATE)
    # G * phi = phi + sigma^2/2 lap(phi) + O(sigma^4), and the spline with the samples as
    # coefficients adds h^2/6 lap: take both off, so the surface no longer shrinks by about
    # sigma^2 x its mean curvature. The Laplacian is taken after one more cell of smoothing:
    # the 7-point stencil alone amplifies the grid-scale remainder of the mesh's creases ~12x,
    # and Newton then stalls near 1e-4 (measured on the torso mesh at 96 x 48)
    smoothed -= (
        (0.5 * sigma**2 + h**2 / 6)
        / h**2
        * laplace(gaussian_filter(smoothed, 1.0, mode="nearest", truncate=TRUNCATE), mode="nearest")
    )
    # float32 coefficients (5e-9 m at the clamp) halve the file; the fit uses the rounded ones
    # too, so a surface read from its file is the surface that was fitted, bit for bit
    spline = SplineField(low, h, smoothed.astype(np.float32).astype(np.float64))
    inside = np.all((mesh.vertices >= low + clamp) & (mesh.vertices <= high - clamp), axis=1)
    value, gradient = spline.evaluate(mesh.vertices[inside], order=1)
    off = value / np.linalg.norm(gradient, axis=1)
    fit = SurfaceFit(
        field=spline,
        smoothing=float(sigma),
        spacing=float(h),
        trusted=float(trusted),
        clamp=float(clamp),
        crease_spacing=float(creases),
        deviation_max=float(np.abs(off).max()),
        deviation_rms=float(np.sqrt(np.mean(off**2))),
        deviation_mean=float(np.mean(off)),
        key=mesh_key(mesh, options),
        refine_levels=int(levels),
        denoise_move=float(move),
    )
    log.info(
        "smooth surface: %d exact samples; mesh vertices %.3g mm from it at most, %.3g mm RMS, "
        "%.3g mm on average (positive: the surface lies inside)",
        exact.size,
        fit.deviation_max * 1e3,
        fit.deviation_rms * 1e3,
        fit.deviation_mean * 1e3,
    )
    return fit
