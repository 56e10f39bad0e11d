"""Avatars: a population body model fitted to a size chart's girths and stature.

A size chart gives girths at heights; the parametric torso and leg (`cloth.bodies.torso`,
`cloth.bodies.leg`) build the simplest convex sections through them. A person's body has a
hollow back, a buttock cleft, breasts and a belly, and that shape moves a girth line's pressure
by far more than the grid does (docs/bodies.md, "Avatars"). An avatar is a realistic body with
the chart's girths: **Anny** (PyPI ``anny``, Apache-2.0; MakeHuman's CC0 assets), a rigged
body model of 13,718 vertices, fitted by `fit_avatar`:

- **What is fitted.** A woman (gender 1, Anny's "young" age anchor 2/3) whose stature (rest
  pose, top to floor) is the chart's ``stature_cm`` (default `DEFAULT_STATURE`) and whose tape
  girths at the chart's heights are the chart's. A tape measures the convex hull of the
  body's section (`cloth.bodies.sections.hull_girth`): on the torso the trunk's section,
  without the arms; on the leg one leg's (Anny's left, ``upperleg01.L``), on its own side of
  the mid-plane x = 0: where heavy thighs touch below the crotch, the tape passes between them
  (without that cut the girth jumps to both thighs' and the fit of leg L stalled 47 mm off).
- **How.** ``scipy.optimize.least_squares`` (trust region, bounded) over the phenotype's height,
  weight, muscle and proportions (`FITTED_PHENOTYPE`) and MakeHuman's tailoring modifiers
  (`TORSO_MODIFIERS`, `LEG_MODIFIERS`), from the model's average, to `TOLERANCE` on every
  girth and the stature; of the bodies that have them, the one nearest the average
  (`REGULARISATION`); a girth the model cannot reach is refused in one line with the range
  it reaches.
- **Pose.** The arms are raised `ARM_RAISE_DEG` and the legs spread `LEG_SPREAD_DEG` from the
  model's A-pose, so that the torso's band is clear of the arms up to the armpits (1.27 m on
  torso M) and the legs' sections are apart up to the thighs.
- **Frame.** Metres, z up, floor (the lowest vertex) at z = 0, front towards +y (as the
  parametric torso), the trunk's axis at x = y = 0.
- **Crop.** The mesh is cut to what a garment on it can cover (`crop`: the chart's span plus
  `CROP_MARGIN`; a leg to its own side of the mid-plane) and the cuts capped, so that it stays
  watertight and its fit is small.

torch, roma and anny are the optional extra ``bodies`` (``pip install 'cloth[bodies]'``) and
are imported here only, inside the functions that need them: nothing else in the package
needs them, and the avatars of the default charts ship in ``data/bodies/avatars/``.

Shapes and units: vertices (V, 3) float, m; faces (F, 3) int; girths and heights m.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.leg import POINTS as LEG_POINTS
from cloth.bodies.leg import read_leg_chart
from cloth.bodies.mesh import MeshBody
from cloth.bodies.sections import hull_girth
from cloth.bodies.torso import LANDMARKS as TORSO_LANDMARKS
from cloth.bodies.torso import read_chart
from cloth.errors import InputError

log = logging.getLogger(__name__)

#: The body model and the extra that brings it.
MODEL = "anny"
EXTRA = "bodies"
#: Stature (m) of a chart without a ``stature_cm`` column: EN 13402-2's reference height of
#: women's sizes, for which the shipped charts' heights are given.
DEFAULT_STATURE = 1.68
#: Phenotype held fixed: a woman (Anny's gender 1) at the "young" age anchor (2/3).
FIXED_PHENOTYPE = {"gender": 1.0, "age": 2.0 / 3.0}
#: Phenotype fitted, each in [0, 1] from the model's average 0.5: with the modifiers the fit
#: has more unknowns than targets, and the trust region ends at the solution nearest the
#: average body (height, weight and the modifiers alone left size L's torso and leg 2-4 mm
#: off, weight at its bound).
FITTED_PHENOTYPE = ("height", "weight", "muscle", "proportions")
#: The pose: arms raised and legs spread from the A-pose, degrees (about the front axis).
ARM_RAISE_DEG = 45.0
LEG_SPREAD_DEG = 5.0
#: The tailoring modifiers fitted to each girth (a local change in [-1, 1]).
TORSO_MODIFIERS = {
    "bust": "measure-bust-circ-incr",
    "underbust": "measure-underbust-circ-incr",
    "waist": "measure-waist-circ-incr",
    "hip": "measure-hips-circ-incr",
}
#: A leg chart has seven girths and the model four leg measures: the lower and upper legs'
#: fat and the calf's muscle (both legs alike) give the fit its other three degrees.
LEG_MODIFIERS = {
    "ankle": ("measure-ankle-circ-incr",),
    "calf": ("measure-calf-circ-incr",),
    "knee": ("measure-knee-circ-incr",),
    "thigh": ("measure-thigh-circ-incr",),
    "lowerleg fat": ("l-lowerleg-fat-incr", "r-lowerleg-fat-incr"),
    "upperleg fat": ("l-upperleg-fat-incr", "r-upperleg-fat-incr"),
    "lowerleg muscle": ("l-lowerleg-muscle-incr", "r-lowerleg-muscle-incr"),
}
#: Largest residual (m) of a fitted girth or the stature; the avatar is refused beyond.
TOLERANCE = 1e-3
#: Residual (m) per unit of a parameter away from the model's average body. The fit has more
#: unknowns than targets: without this its answer was one of many bodies with the chart's
#: girths, picked by round-off (torso M's parameters moved by 0.74 between two builds of the
#: model's cache); with it, the body nearest the average that has them (the girths move by
#: about 0.005 mm).
REGULARISATION = 1e-3
#: The crop keeps the chart's span plus this much (m) above and below.
CROP_MARGIN = 0.05
#: The cropped mesh's coordinates are rounded to this many decimals of a metre (1 nm) before
#: float32, so round-off on a cut plane does not reach the file's bytes.
SNAP_DECIMALS = 9
#: Finite-difference step of the fit (relative, in the parameters' units, 0-1), taken both ways:
#: a local change has a kink at 0 (its "incr" target above, its "decr" below), where a
#: one-sided difference sees one slope only and the fit of leg L stalled 32 mm off.
DIFF_STEP = 1e-3


@dataclass(frozen=True)
class ChartTargets:
    """What an avatar is fitted to: one size of a torso or leg chart.

    Attributes
    ----------
    kind : {'torso', 'leg'}
    size : str
    girth, height : dict, m
        Girth line -> tape girth, and -> its height above the floor.
    stature : float, m
    span : (2,) float, m
        The heights a garment on this body can cover: the torso chart's bottom to top, the
        leg's floor to G.
    ranges : dict, m
        Girth line -> (low, high) where the chart gives the size's girth as a range.
    """

    kind: str
    size: str
    girth: dict[str, float]
    height: dict[str, float]
    stature: float
    span: tuple[float, float]
    #: girth line -> (low, high), m: the girths the size fits, where the chart gives a range
    ranges: dict[str, tuple[float, float]] = field(default_factory=dict)
    #: girth lines measured but not fitted: the body model's own, given the others (a wearer's
    #: girths that neither her population nor the size's ranges set, `cloth.bodies.wearers`)
    free: tuple[str, ...] = ()
    #: phenotype parameters held at a value rather than fitted (``muscle``, ``proportions``:
    #: a wearer at an extreme of the body model's shape with her girths, `cloth.bodies.wearers`)
    pinned: dict[str, float] = field(default_factory=dict)

    @property
    def fitted(self) -> list[str]:
        """The girth lines the fit matches (all but `free`)."""
        return [n for n in self.girth if n not in self.free]


def chart_rows(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    """A chart's columns and its rows by column (its ``#`` comment lines left out), as its
    readers take them."""
    import csv

    lines = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    reader = csv.DictReader(lines)
    rows = list(reader)
    return [c.strip() for c in reader.fieldnames or []], rows


def chart_kind(chart: str | Path, columns: list[str] | None = None) -> str:
    """'torso' or 'leg': a chart's kind, read from its columns (a torso chart has ``bust_cm``
    or the range ``bust_min_cm``, a leg chart ``B_cm`` or ``B_min_cm``; ``columns``: the
    chart's, where already read); one line naming the file for a chart of neither kind."""
    path = Path(chart)
    if columns is None:
        if not path.is_file():
            raise InputError("size chart not found; check the path", path)
        columns = chart_rows(path)[0]
    if "bust_cm" in columns or "bust_min_cm" in columns:
        return "torso"
    if "B_cm" in columns or "B_min_cm" in columns:
        return "leg"
    raise InputError(
        "neither a torso chart (bust_cm or bust_min_cm, ...) nor a leg chart (B_cm or "
        "B_min_cm, ...); see "
        "data/bodies/size_chart.csv and leg_chart.csv for the columns",
        path,
        "header",
    )


def chart_targets(chart: str | Path, size: str) -> ChartTargets:
    """Size ``size`` of the torso or leg chart ``chart`` (`chart_kind`); one line naming the
    file for a chart of neither kind, an unknown size or a stature past any adult's."""
    path = Path(chart)
    if not path.is_file():
        raise InputError("size chart not found; check the path", path)
    columns, rows = chart_rows(path)
    kind = chart_kind(path, columns)
    sizes = read_chart(path) if kind == "torso" else read_leg_chart(path)
    if size not in sizes:
        raise InputError(f"unknown size {size!r}; the chart has {', '.join(sizes)}", path, "size")
    spec = sizes[size]
    stature = _stature(rows, path, size)
    if not 1.2 <= stature <= 2.2:
        raise InputError(
            f"size {size}: stature {stature * 100:g} cm is not an adult's; give stature_cm in cm",
            path,
            "stature_cm",
        )
    if kind == "torso":
        names = TORSO_LANDMARKS
        span = (spec.height["bottom"], spec.height["top"])
    else:
        names = LEG_POINTS
        span = (0.0, spec.height["G"])
    return ChartTargets(
        kind=kind,
        size=size,
        girth={n: float(spec.girth[n]) for n in names},
        height={n: float(spec.height[n]) for n in names},
        stature=stature,
        span=(float(span[0]), float(span[1])),
        ranges={n: (float(lo), float(hi)) for n, (lo, hi) in spec.girth_range.items()},
    )


def _stature(rows: list[dict[str, str]], path: Path, size: str) -> float:
    """A size's ``stature_cm`` (m) from the chart's ``rows``, `DEFAULT_STATURE` where the chart
    has no such column."""
    for row in rows:
        if (row.get("size") or "").strip() == size:
            text = (row.get("stature_cm") or "").strip()
            if not text:
                return DEFAULT_STATURE
            try:
                return float(text) / 100
            except ValueError:
                raise InputError(
                    f"size {size}: stature_cm {text!r} is not a number; give it in cm",
                    path,
                    "stature_cm",
                ) from None
    return DEFAULT_STATURE


@dataclass
class Avatar:
    """A fitted avatar (`fit_avatar`).

    Attributes
    ----------
    vertices : (V, 3) float, m
        z up, floor at 0, front +y; rounded to float32 (what its PLY file holds).
    faces : (F, 3) int
        Outward oriented; watertight.
    targets : ChartTargets
    parameters : dict
        Every parameter of the model: the phenotype (fixed and fitted) and each local change
        fitted, by Anny's names.
    girth : dict, m
        The avatar's tape girth at each of the chart's heights.
    stature : float, m
    loop_point : (2,) float, m
        A point inside the part the garment wraps (the trunk's axis, or the fitted leg's at
        mid-span), from which `cloth.bodies.sections.follow` finds that part row by row.
    side : float
        The side of the mid-plane x = 0 the fitted leg is on (-1 or +1; 0: a torso).
    seconds : float
        Time the fit took (not the model's load).
    evaluations : int
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    targets: ChartTargets
    parameters: dict[str, float]
    girth: dict[str, float]
    stature: float
    loop_point: tuple[float, float]
    seconds: float = 0.0
    evaluations: int = 0
    versions: dict[str, str] = field(default_factory=dict)
    posed: bool = True
    side: float = 0.0

    def residuals(self) -> dict[str, float]:
        """Avatar minus chart (m): every fitted girth, and the stature."""
        out = {n: self.girth[n] - self.targets.girth[n] for n in self.targets.fitted}
        out["stature"] = self.stature - self.targets.stature
        return out


def _without_stderr(call) -> None:
    """``call()`` with the process's stderr (file descriptor 2, which native code writes to)
    sent to the null device: a refusal stays one line."""
    import os
    import sys

    sys.stderr.flush()
    saved, null = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 2)
        call()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


def _modules():
    """torch, roma and anny, or one line saying how to install them."""
    import importlib.util

    missing = [name for name in ("anny", "torch") if importlib.util.find_spec(name) is None]
    try:
        if missing:  # name what the user installs, not one of its dependencies
            raise ImportError(name=missing[0])
        import warp

        # anny's skinning initialises warp: no banner and no module timings on stdout (warp
        # 1.19 reads log_level, earlier releases quiet)
        warp.config.quiet = True
        if hasattr(warp, "LOG_WARNING"):
            warp.config.log_level = warp.LOG_WARNING
        _without_stderr(warp.init)  # nor its native warning that no CUDA driver is found
        import anny
        import roma
        import torch
    except ImportError as exc:
        raise InputError(
            f"avatars need the body model ({exc.name} is not installed): pip install "
            f"'cloth[{EXTRA}]' (torch, anny); the default charts' avatars ship in "
            "data/bodies/avatars/ and need none of it",
            field="bodies extra",
        ) from None
    return torch, roma, anny


class _Model:
    """Anny with the pose of this module, evaluated to numpy in the avatar's frame."""

    def __init__(self, posed: bool = True) -> None:
        torch, roma, anny = _modules()
        self.torch = torch
        torch.set_num_threads(1)  # one thread: bit-identical fits, whatever the machine
        start = time.perf_counter()
        # the phenotype blend shapes as loaded: Anny's default compacts them into a basis by an
        # SVD whose basis differs with round-off between two builds of its cache (fits then
        # differed in the last bits); loaded as they are, two caches give the same body
        self.model = anny.Anny(local_changes="default", phenotype_blendshapes="original")
        log.info(
            "body model Anny %s loaded in %.1f s", anny.__version__, time.perf_counter() - start
        )
        self.faces = self.model.faces.detach().cpu().numpy().astype(np.int64)
        self.bones = list(self.model.bone_labels)
        self.versions = {"anny": anny.__version__, "torch": torch.__version__}

        def about_y(degrees: float):
            rotation = torch.eye(4, dtype=torch.float64)[None].clone()
            vector = torch.tensor([[0.0, np.radians(degrees), 0.0]], dtype=torch.float64)
            rotation[0, :3, :3] = roma.rotvec_to_rotmat(vector)
            return rotation

        # rotations about the model's front axis at each bone's head: -y lowers Anny's left
        # (x > 0) arm and spreads its right leg
        self.pose = (
            {
                "upperarm01.L": about_y(-ARM_RAISE_DEG),
                "upperarm01.R": about_y(ARM_RAISE_DEG),
                "upperleg01.L": about_y(-LEG_SPREAD_DEG),
                "upperleg01.R": about_y(LEG_SPREAD_DEG),
            }
            if posed
            else None
        )

    def __call__(self, phenotype: dict, changes: dict) -> tuple[NDArray, float, dict]:
        """Posed vertices in the avatar's frame (float32-rounded), the rest stature and the
        posed bones' heads (name -> (3,) m, same frame)."""
        with self.torch.no_grad():
            out = self.model(
                pose_parameters=self.pose,
                phenotype_kwargs=phenotype,
                local_changes_kwargs=changes,
            )
        rest = out["rest_vertices"][0].cpu().numpy()
        stature = float(rest[:, 2].max() - rest[:, 2].min())
        flip = np.array([-1.0, -1.0, 1.0])  # the model faces -y: turn it to face +y
        vertices = out["vertices"][0].cpu().numpy().astype(np.float64) * flip
        floor = vertices[:, 2].min()
        root = out["bone_poses"][0, self.bones.index("root"), :3, 3].cpu().numpy() * flip
        shift = np.array([root[0], root[1], floor])
        vertices = (vertices - shift).astype(np.float32).astype(np.float64)
        heads = {
            name: out["bone_poses"][0, k, :3, 3].cpu().numpy() * flip - shift
            for k, name in enumerate(self.bones)
        }
        return vertices, stature, heads


def axis_point(kind: str, heads: dict[str, NDArray], z: float) -> tuple[float, float]:
    """A point (x, y, m) inside the part a tape goes around at height ``z``: the trunk's axis
    (x = y = 0), or the fitted leg's, interpolated along its bones (hip, knee, ankle)."""
    if kind == "torso":
        return (0.0, 0.0)
    chain = np.array([heads[b] for b in ("upperleg01.L", "lowerleg01.L", "foot.L")])
    order = np.argsort(chain[:, 2])
    x = float(np.interp(z, chain[order, 2], chain[order, 0]))
    y = float(np.interp(z, chain[order, 2], chain[order, 1]))
    return (x, y)


def leg_side(kind: str, heads: dict[str, NDArray]) -> float:
    """The side of the mid-plane x = 0 the fitted leg is on (-1 or +1; 0 for a torso)."""
    if kind == "torso":
        return 0.0
    return float(np.sign(heads["upperleg01.L"][0]))


def fit_avatar(chart: str | Path, size: str, posed: bool = True) -> Avatar:
    """The avatar of size ``size`` of the torso or leg chart ``chart`` (module docstring);
    ``posed=False``: in the model's own A-pose, arms hanging (a full-body scan's pose)."""
    return fit_targets(chart_targets(chart, size), chart, posed)


def fit_targets(targets: ChartTargets, chart: str | Path, posed: bool = True) -> Avatar:
    """The avatar with the girths and stature of ``targets`` (one size of ``chart``, or one of
    its wearers, `cloth.bodies.wearers`); refused in one line naming ``chart`` where the model
    cannot reach them."""
    from scipy.optimize import least_squares

    model = _Model(posed)
    if targets.kind == "torso":
        groups = {name: (TORSO_MODIFIERS[name],) for name in TORSO_LANDMARKS}
    else:
        groups = dict(LEG_MODIFIERS)
    names = list(targets.girth)
    matched = targets.fitted
    free = [p for p in FITTED_PHENOTYPE if p not in targets.pinned]
    fixed = {**FIXED_PHENOTYPE, **targets.pinned}

    def unpack(x: NDArray) -> tuple[dict, dict]:
        fitted = len(free)
        phenotype = {**fixed, **dict(zip(free, map(float, x), strict=False))}
        changes = {
            label: float(value)
            for value, labels in zip(x[fitted:], groups.values(), strict=True)
            for label in labels
        }
        return phenotype, changes

    def measure(x: NDArray) -> tuple[dict[str, float], float, NDArray, dict]:
        vertices, stature, heads = model(*unpack(x))
        body = MeshBody(vertices, model.faces)
        side = leg_side(targets.kind, heads)
        girth = {
            n: hull_girth(
                body, targets.height[n], axis_point(targets.kind, heads, targets.height[n]), side
            )
            for n in names
        }
        return girth, stature, vertices, heads

    fitted = len(free)
    x0 = np.array([0.5] * fitted + [0.0] * len(groups))

    def residual(x: NDArray) -> NDArray:
        girth, stature, _, _ = measure(x)
        misses = [stature - targets.stature, *(girth[n] - targets.girth[n] for n in matched)]
        return np.concatenate([misses, REGULARISATION * (x - x0)])

    start = time.perf_counter()
    low = np.array([0.0] * fitted + [-1.0] * len(groups))
    high = np.array([1.0] * fitted + [1.0] * len(groups))
    solution = least_squares(
        residual,
        x0,
        jac="3-point",
        bounds=(low, high),
        diff_step=DIFF_STEP,
        xtol=1e-12,
        ftol=1e-12,
        gtol=1e-12,
    )
    girth, stature, vertices, heads = measure(solution.x)
    seconds = time.perf_counter() - start
    phenotype, changes = unpack(solution.x)
    mid = 0.5 * (targets.span[0] + targets.span[1])
    avatar = Avatar(
        vertices=vertices,
        faces=model.faces,
        targets=targets,
        parameters={**phenotype, **changes},
        girth=girth,
        stature=stature,
        loop_point=axis_point(targets.kind, heads, mid),
        side=leg_side(targets.kind, heads),
        seconds=seconds,
        evaluations=int(solution.nfev),
        versions=model.versions,
        posed=posed,
    )
    _check_reached(avatar, lambda x: measure(x)[0], solution.x, chart)
    log.info(
        "avatar %s %s: %d evaluations in %.1f s; residuals %s",
        targets.kind,
        targets.size,
        solution.nfev,
        seconds,
        ", ".join(f"{k} {v * 1e3:+.3f} mm" for k, v in avatar.residuals().items()),
    )
    return avatar


def _check_reached(avatar: Avatar, girths, x: NDArray, chart) -> None:
    """Refuse an avatar with a residual over `TOLERANCE` in one line. Each girth's span is
    what it reaches when each parameter but the height moves from end to end, one at a time,
    from the best fit; the line names the girth whose chart value lies furthest outside its
    span (a bust no body of the other girths has), else the one that misses most, with its
    best value and its span."""
    residuals = avatar.residuals()
    worst = max(residuals, key=lambda key: abs(residuals[key]))
    if abs(residuals[worst]) <= TOLERANCE:
        return
    size = avatar.targets.size
    if worst == "stature":
        raise InputError(
            f"size {size}: the body model cannot reach a stature of "
            f"{avatar.targets.stature * 100:.1f} cm (best {avatar.stature * 100:.1f} cm); give "
            "a stature_cm the model reaches",
            chart,
            "stature_cm",
        )
    trials = [avatar.girth]
    phenotypes = len(FITTED_PHENOTYPE) - len(avatar.targets.pinned)
    for index in range(1, len(x)):  # all but the height
        for end in (0.0 if index < phenotypes else -1.0, 1.0):
            trial = x.copy()
            trial[index] = end
            trials.append(girths(trial))
    span = {
        n: (min(t[n] for t in trials), max(t[n] for t in trials)) for n in avatar.targets.fitted
    }
    target = avatar.targets.girth
    outside = {n: abs(target[n] - np.clip(target[n], *span[n])) / target[n] for n in span}
    name = max(outside, key=outside.get) if max(outside.values()) > 0 else worst
    raise InputError(
        f"size {size}: the body model cannot reach the {name} girth of "
        f"{target[name] * 100:.1f} cm at {avatar.targets.height[name] * 100:.1f} cm with the "
        f"chart's other girths (best {avatar.girth[name] * 100:.1f} cm; one parameter at a time "
        f"from there it spans {span[name][0] * 100:.1f}-{span[name][1] * 100:.1f} cm); give "
        "girths a body has",
        chart,
        f"{name}_cm",
    )


def crop(avatar: Avatar) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The avatar's mesh cut to its chart's span plus `CROP_MARGIN` (not below the floor), and
    a leg's to its own side of the mid-plane x = 0 (one leg; where the thighs touch, the cut is
    where a tape passes between them), the cuts capped (trimesh's plane slice with caps; shapely,
    rtree and ``mapbox-earcut`` are in the extra): watertight, outward oriented; float32-rounded
    vertices."""
    import trimesh

    mesh = trimesh.Trimesh(avatar.vertices, avatar.faces, process=False)
    low, high = avatar.targets.span
    if low - CROP_MARGIN > float(avatar.vertices[:, 2].min()):
        mesh = mesh.slice_plane([0.0, 0.0, low - CROP_MARGIN], [0.0, 0.0, 1.0], cap=True)
    mesh = mesh.slice_plane([0.0, 0.0, high + CROP_MARGIN], [0.0, 0.0, -1.0], cap=True)
    if avatar.side != 0.0:
        mesh = mesh.slice_plane([0.0, 0.0, 0.0], [avatar.side, 0.0, 0.0], cap=True)
    mesh.merge_vertices()
    mesh.remove_unreferenced_vertices()
    if not (mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0):
        raise InputError(
            "the cropped avatar is not a closed, outward mesh; report this with the chart",
            field="crop",
        )
    # a cut leaves its plane's points at round-off (1e-19 m) of either sign, which differs between
    # machines; snapped to the nanometre (and -0 made 0), the file is the same bytes everywhere
    snapped = np.round(np.asarray(mesh.vertices, dtype=np.float64), SNAP_DECIMALS) + 0.0
    vertices = snapped.astype(np.float32).astype(np.float64)
    return vertices, np.asarray(mesh.faces, dtype=np.int64)
