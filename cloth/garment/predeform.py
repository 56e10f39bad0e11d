"""Pre-deformation: cut a tube pattern and wrap it around the body (the paper's initial state).

Pattern. A tube of n nodes around (the grid's weft) and m rows up, rows at heights z_j from
``bottom`` to ``top``, equally spaced or graded toward both edges (``garment.row_grading``,
`cloth.garment.rows`). Rest circumference of row j: (1 - r(z_j)) x the convex-hull
girth of the body at z_j (a graded pattern, how compression garments are cut; r the reduction,
a number or a profile over height, `cloth.case.profile`), or a constant ``circumference`` (a
rectangle). Warp rest length between rows j and j+1: (1 - lengthwise reduction at their
middle) (z_{j+1} - z_j).

Wrapping. Each row is placed on the convex hull of the body's cross-section at its height (the
fabric bridges concavities such as the cleavage; with ``loop_point`` only the loop enclosing
that point, e.g. the torso between the arms; without it, where a row meets several loops, the
largest), at equal arc length, starting at the centre back (the hull's crossing of the ray from
its centroid towards -y) and running counter-clockwise seen from above. Nodes closer to the
surface than ``offset`` (default 0.1 mm) are then moved to the closest surface point plus
``offset`` along the outward normal, so every node starts on or just outside the body: signed
distance in [0, offset] where the hull touches the body, larger where it bridges a concavity.

Movement (the paper's three kinds): the lower and upper rows are ``fixed``, ``sliding`` (height
held, free around and in/out) or ``free``; every other node is free, and any node may rest on
the body surface (contact flag; relaxation keeps it on or outside).
"""

from __future__ import annotations

import json
import logging
from collections.abc import Mapping
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body, hull_polygon, loop_around
from cloth.bodies.sections import follow, loop_area
from cloth.case import Case
from cloth.errors import InputError
from cloth.garment.cut import NO_PLACEMENT, BodyCut, TableCut, cut_girths, placement
from cloth.garment.grid import FIXED, FREE, SLIDING, WEFT, Grid, build_grid
from cloth.garment.layout import Layout, band_circumference, band_heights, row_zones
from cloth.garment.pieces import garment_grid, with_pieces
from cloth.garment.rows import row_heights
from cloth.garment.state import State, grid_fabric
from cloth.garment.worn import set_strains
from cloth.materials.curves import Fabric
from cloth.progress import progress

log = logging.getLogger(__name__)

EDGE_CONSTRAINT = {"fixed": FIXED, "sliding": SLIDING, "free": FREE}


def _start(hull: NDArray[np.float64]) -> float:
    """Arc length along ``hull`` where the ray from its centroid towards -y crosses it."""
    centre = hull.mean(axis=0)
    a, b = hull, np.roll(hull, -1, axis=0)
    seg = np.linalg.norm(b - a, axis=1)
    cumulative = np.concatenate(([0.0], np.cumsum(seg)))
    # segment crosses the vertical line x = centre_x below the centre
    dx = b[:, 0] - a[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (centre[0] - a[:, 0]) / dx
    y = a[:, 1] + t * (b[:, 1] - a[:, 1])
    hits = np.flatnonzero((t >= 0) & (t < 1) & (y < centre[1]))
    if hits.size == 0:
        return 0.0
    k = hits[np.argmin(y[hits])]
    return float(cumulative[k] + t[k] * seg[k])


#: Grids above this many nodes show their progress while they are wrapped (a bar on a
#: terminal, log lines otherwise).
PROGRESS_NODES = 50_000


def place_on_hull(hull: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    """n points at equal arc length on a closed counter-clockwise polygon ((H, 2)), from the
    centre back."""
    a, b = hull, np.roll(hull, -1, axis=0)
    seg = np.linalg.norm(b - a, axis=1)
    cumulative = np.concatenate(([0.0], np.cumsum(seg)))
    perimeter = cumulative[-1]
    s = np.mod(_start(hull) + perimeter * np.arange(n) / n, perimeter)
    k = np.clip(np.searchsorted(cumulative, s, side="right") - 1, 0, len(seg) - 1)
    t = (s - cumulative[k]) / seg[k]
    return a[k] + t[:, None] * (b[k] - a[k])


def row_hulls(
    body: Body,
    heights: NDArray[np.float64],
    loop_point: list[float] | None,
    nodes_per_row: int = 0,
) -> list[NDArray[np.float64]]:
    """Convex hull per row of the body's cross-section: of the loops around ``loop_point`` on
    every row; else, where rows meet several loops (arms beside the torso, two legs), of the
    part the garment wraps, followed from the middle row (`cloth.bodies.sections.follow`): the
    loops around the body's own ``loop_point`` there (an avatar's torso or leg), else the
    largest; else of the one loop. Progress is shown for grids above `PROGRESS_NODES`
    (`cloth.progress`)."""
    low, high = body.z_range
    large = len(heights) * nodes_per_row > PROGRESS_NODES
    sections = []
    for z in progress(
        heights, desc="predeform: row sections", unit="row", show=None if large else False
    ):
        if not low <= z <= high:
            raise InputError(
                f"row height {z:.6g} m is outside the body ({low:.6g} to {high:.6g} m); choose "
                "garment bottom and top within the body",
                field="garment",
            )
        sections.append(body.sections(float(z)))
    if loop_point is not None:
        return [hull_polygon(loop_around(loops, loop_point)) for loops in sections]
    several = [k for k, loops in enumerate(sections) if len(loops) > 1]
    if not several:
        return [hull_polygon(loops) for loops in sections]
    start = len(sections) // 2
    anchor = getattr(body, "loop_point", None)
    if anchor is not None:
        first = loop_around(sections[start], anchor)
    else:
        first = [max(sections[start], key=loop_area)]
    parts = follow(sections, start, first)
    share = [
        sum(loop_area(loop) for loop in parts[k]) / sum(loop_area(loop) for loop in sections[k])
        for k in several
    ]
    log.warning(
        "%d of %d rows (%.4g-%.4g m) meet up to %d section loops; the garment wraps the part "
        "%s, followed row by row (%.0f-%.0f %% of the section's area); give "
        "garment.loop_point to choose another",
        len(several),
        len(heights),
        heights[several[0]],
        heights[several[-1]],
        max(len(sections[k]) for k in several),
        "around the body's loop point" if anchor is not None else "of the largest loop",
        100 * min(share),
        100 * max(share),
    )
    return [hull_polygon(loops) for loops in parts]


def wrap(
    body: Body, hulls: list[NDArray], heights: NDArray, n: int, offset: float
) -> NDArray[np.float64]:
    """Node positions ((m*n, 3), m): each row on its hull, then lifted to >= offset outside."""
    rows = [
        np.column_stack([place_on_hull(hull, n), np.full(n, z)])
        for hull, z in zip(hulls, heights, strict=True)
    ]
    x = np.concatenate(rows)
    distance, closest, normal = body.query(x)
    near = distance < offset
    x[near] = closest[near] + offset * normal[near]
    return x


#: Nodes around the coarsest grid of ``grid: auto``.
START_AROUND = 12


def row_girths(
    body: Body, hulls: list[NDArray], heights: NDArray, loop_point: tuple[float, float] | None
) -> NDArray[np.float64]:
    """(m,) float, m: the rows' convex-hull girths; without a loop point, the body's own hull
    girth where the row meets one loop (exact for closed forms)."""
    hull_girth = cut_girths(hulls)
    if loop_point is None:
        whole = np.array([body.girth(float(z))[1] for z in heights])
        one_loop = np.isclose(whole, hull_girth, rtol=1e-3)  # else: the largest of several
        hull_girth = np.where(one_loop, whole, hull_girth)
    return hull_girth


def start_grid(body: Body, bottom: float, top: float) -> tuple[int, int]:
    """The coarsest grid of ``grid: auto``: `START_AROUND` nodes around, and rows as far apart
    as the nodes are around the body's girth halfway up (square cells; at least 3 rows)."""
    girth = float(body.girth(0.5 * (bottom + top))[1])
    rows = 1 + round((top - bottom) / (girth / START_AROUND))
    return START_AROUND, max(3, int(rows))


def predeform(
    case: Case,
    fabric: Fabric,
    body: Body,
    body_record: dict,
    source: str = "case",
    grid: tuple[int, int] | None = None,
    pattern: BodyCut | TableCut | None = None,
    fabrics: Mapping[str, Fabric] | None = None,
) -> State:
    """Build the initial state of a case: pattern, wrapped positions, constraints. Reads no file.

    Parameters
    ----------
    case : Case
        The case (`cloth.case.case.validate_case`; docs/config.md).
    fabric : Fabric
        The case's material (`cloth.files.material.load_fabric`).
    body : Body
        The case's body (`cloth.files.body.body_from_config`).
    body_record : dict
        The body's record for state files (`cloth.files.body.body_from_config`'s second value);
        a fitted surface's record is added to a copy.
    source : str
        Name of the case in error messages.
    grid : (int, int), optional
        Nodes around and rows, instead of the case's (a coarser level of its error estimate,
        a step of ``grid: auto``); with ``grid: auto`` and none given, `start_grid`.
    pattern : BodyCut or TableCut, optional
        The garment's pattern (`cloth.garment.cut`); needed where the case gives
        ``garment.pattern`` (`cloth.stages.case.case_cut`); default the case's own graded
        pattern on ``body``.
    """
    garment = case.garment
    body_ref = dict(body_record)
    if grid is None:
        grid = start_grid(body, garment.bottom, garment.top) if garment.auto else garment.grid
    n, m = grid
    cut_heights = row_heights(garment.bottom, garment.top, m, garment.row_grading)
    pieces = garment.pieces
    if pieces.bands:
        cut_heights = band_heights(cut_heights, pieces, garment.bottom, garment.top)
    marks = {**body_record.get("landmarks", {}), **case.landmarks}
    if pattern is None:
        if garment.pattern is not None:
            raise ValueError("a case with a pattern needs its cut (cloth.stages.case.case_cut)")
        pattern = BodyCut(body, garment, body_record.get("landmarks", {}), case.landmarks)
    place, shift = NO_PLACEMENT, 0.0
    if garment.pattern is not None:
        place, shift = placement(garment.place, pattern.lines, marks, source)
        log.info(
            "predeform: the pattern placed by %s, its cut heights shifted by %+.4g m",
            "its cut frame" if place == NO_PLACEMENT else f"girth line {place}",
            shift,
        )
    heights = cut_heights + shift if shift else cut_heights
    log.info("predeform: %s nodes (%d x %d) on the body", f"{n * m:,}", n, m)
    hulls = row_hulls(body, heights, garment.loop_point, n)
    hull_girth = row_girths(body, hulls, heights, garment.loop_point)
    if isinstance(pattern, BodyCut):
        cut_girth = hull_girth
        if pattern.body is not body or shift:
            cut_hulls = row_hulls(pattern.body, cut_heights, garment.loop_point, n)
            cut_girth = row_girths(pattern.body, cut_hulls, cut_heights, garment.loop_point)
        rows = pattern.rows(cut_heights, cut_girth, source)
    else:
        rows = pattern.rows(cut_heights, source)
    circumference, rest_v, row_reduction = rows.circumference, rows.rest_v, rows.reduction
    zone = row_zones(cut_heights, pieces, garment.bottom, garment.top)
    if pieces.bands:
        girth = hull_girth if rows.cut_girth is None else rows.cut_girth
        circumference = band_circumference(circumference, girth, zone, pieces)
        if row_reduction is not None:  # a band's rows: its own reduction of the girth
            row_reduction = np.where(zone >= 0, 1.0 - circumference / girth, row_reduction)
    moduli = garment.moduli
    around = garment.around
    worn = set_strains(garment, fabric, source)
    if worn:  # the set lengthens the pattern in each direction (cloth.garment.worn)
        up = "warp" if around == "weft" else "weft"
        circumference = circumference * (1.0 + worn[around])
        rest_v = rest_v * (1.0 + worn[up])
        log.info("predeform: worn garment, set strain weft %.4g, warp %.4g", *worn.values())
    grid = build_grid(
        n,
        m,
        circumference,
        rest_v,
        grid_fabric(fabric, around),
        closed=True,
        **moduli,
    )
    if pieces.any:
        grid = garment_grid(grid, Layout.of(case), fabric, fabrics or {}, cut_heights, zone)
    offset = garment.offset
    x = wrap(body, hulls, heights, n, offset)
    constraint = np.full(grid.n_nodes, FREE, dtype=np.int8)
    edge = EDGE_CONSTRAINT[garment.edges]
    constraint[:n] = edge
    constraint[-n:] = edge
    distance = body.query(x)[0]
    contact = (distance <= offset * (1 + 1e-6) + 1e-12).astype(np.int8)
    strain = hull_girth / circumference - 1.0
    log.info(
        "predeform: %d x %d grid, rows %.4g-%.4g m, hull girth %.4g-%.4g m, initial weft strain "
        "%.4g-%.4g, %d of %d nodes on the body",
        n,
        m,
        heights[0],
        heights[-1],
        hull_girth.min(),
        hull_girth.max(),
        strain.min(),
        strain.max(),
        int(contact.sum()),
        grid.n_nodes,
    )
    record = getattr(body, "record", None)
    if record is not None:  # a fitted surface: its smoothing and deviation from the mesh
        body_ref["surface"] = record()
    return State(
        grid=grid,
        x=x,
        constraint=constraint,
        on_body=contact,
        fabric=fabric,
        around=around,
        case=case,
        skin=case.skin,
        body=body_ref,
        fabrics=dict(fabrics or {}) if pieces.any else {},
        layout=Layout.of(case) if pieces.any else None,
        moduli=moduli,
        attrs={
            "offset": offset,
            "hull_girth": hull_girth.tolist(),
            "cut_height": cut_heights.tolist(),
            "cut_shift": shift,
            **({} if garment.pattern is None else {"cut_lines": json.dumps(_marks(pattern))}),
            **({} if row_reduction is None else {"row_reduction": row_reduction.tolist()}),
            **({"row_band": zone.tolist()} if pieces.bands else {}),
            **({} if rows.cut_girth is None else {"cut_girth": rows.cut_girth.tolist()}),
            **_table_attr(pattern),
            **{f"set_strain_{d}": s for d, s in worn.items()},
        },
    )


def _table_attr(pattern: BodyCut | TableCut) -> dict[str, str]:
    """A pattern file's rows for the state (`cloth.stages.cuts.state_cut`); none for a cut."""
    return {"pattern_table": json.dumps(pattern.to_attr())} if isinstance(pattern, TableCut) else {}


def _marks(pattern: BodyCut | TableCut) -> dict[str, float]:
    """The girth lines a pattern's reduction profile is evaluated at (cut heights, m)."""
    return {**pattern.lines, **getattr(pattern, "extra", {})}


def recut(state: State, row_reduction: NDArray[np.float64]) -> Grid:
    """``state``'s grid cut with the row reductions ``row_reduction`` ((m,), 1) in place of its
    own (``attrs['row_reduction']``): each row's rest circumference scaled by (1 - new) /
    (1 - old), the warp as it was; the rest lengths and areas of every spring family follow
    (`build_grid`). For the sensitivities (`cloth.results.sensitivity`)."""
    grid = state.grid
    old = state.row_values("row_reduction")
    if old is None:
        raise ValueError("recut needs a graded pattern (a state with row_reduction)")
    weft = grid.rest_length[grid.family_slices[WEFT]].reshape(grid.m, -1).sum(axis=1)
    circumference = weft * (1.0 - np.asarray(row_reduction)) / (1.0 - old)
    recut = _plain_grid(state, circumference)
    if grid.materials is None:
        return recut
    # a garment of several fabrics: each spring's area over the plain grid's is its fabric's
    # thickness and its strip's share, neither of which the cut changes
    ratio = grid.area / _plain_grid(state, weft).area
    return with_pieces(recut, grid.materials, recut.area * ratio)


def _plain_grid(state: State, circumference: NDArray[np.float64]) -> Grid:
    """``state``'s grid of one fabric with the rows' rest ``circumference`` ((m,), m)."""
    grid = state.grid
    return build_grid(
        grid.n,
        grid.m,
        circumference,
        grid.rest_uv[:: grid.n, 1],
        grid_fabric(state.fabric, state.around),
        closed=grid.closed,
        **state.moduli,
    )


def with_profile(state: State, values: NDArray[np.float64]) -> State:
    """``state`` with its reduction profile's knot values replaced by ``values`` ((K,), 1): the
    case says so, the grid is `recut`, the positions stay (a warm start for the new pattern)."""
    garment = state.case.garment
    profile = garment.reduction_profile.with_values(np.asarray(values, dtype=float))
    marks = {**state.body.get("landmarks", {}), **state.case.landmarks}
    if "cut_lines" in state.attrs:  # a pattern cut for another body: its girth lines
        marks = json.loads(state.attrs["cut_lines"])
    rows = profile.evaluate(state.row_values("cut_height"), marks)
    band = state.row_values("row_band")
    if band is not None:  # a band's rows keep its own reduction
        rows = np.where(band >= 0, state.row_values("row_reduction"), rows)
    data = state.case.to_dict()
    data["garment"]["reduction"] = profile.to_block()
    attrs = {**state.attrs, "row_reduction": rows.tolist()}
    return replace(state, grid=recut(state, rows), case=Case.from_dict(data), attrs=attrs)


def with_bands(state: State, reductions: Mapping[int, float]) -> State:
    """``state`` with band k's reduction replaced by ``reductions[k]`` (1): the case says so,
    its rows are `recut`, the positions stay (a warm start, as `with_profile`)."""
    band = state.row_values("row_band")
    rows = state.row_values("row_reduction")
    if band is None or rows is None:
        raise ValueError("with_bands needs a graded pattern with bands")
    data = state.case.to_dict()
    rows = rows.copy()
    for k, value in reductions.items():
        rows[band == k] = float(value)
        data["garment"]["bands"][k]["reduction"] = float(value)
    attrs = {**state.attrs, "row_reduction": rows.tolist()}
    return replace(state, grid=recut(state, rows), case=Case.from_dict(data), attrs=attrs)
