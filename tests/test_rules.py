"""Rules checked on many inputs, each against a second route written here: a probe's reading on
a grid whose rows gather, every guard of the levels and the grid at its exact threshold, and the
tape's girth of every shipped avatar's girth lines against a convex hull of its own."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.path import Path as PolygonPath
from scipy.spatial import ConvexHull

from cloth.bodies.mesh import MeshBody
from cloth.bodies.sections import hull_girth
from cloth.case.case import validate_case
from cloth.case.reading import Reading
from cloth.errors import InputError
from cloth.results.bands import probe_readings
from cloth.stages.levels import MIN_AROUND, MIN_ROWS, coarser_grids
from tests import inventory

AVATARS = inventory.ROOT / "data" / "bodies" / "avatars"


def gathered_tube(seed: int, around: int, rows: int):
    """Nodes of a tube about an off-centre axis, unevenly spaced around (clustered on one
    side) and in height (the rows gather near the middle, as where the warp is slack), with
    each node's tributary area and a contact force that varies around: (x (N, 3) m, force (N,)
    N, area (N,) m2, centre (2,) m, radius m)."""
    rng = np.random.default_rng(seed)
    centre = rng.uniform(-0.05, 0.05, 2)
    radius = rng.uniform(0.06, 0.15)
    u = np.sort(rng.uniform(0, 1, around))
    theta = 2 * np.pi * (u + 0.3 * np.sin(2 * np.pi * u) / (2 * np.pi))  # clustered
    s = np.linspace(-1, 1, rows)
    z = 0.5 + 0.15 * np.sign(s) * np.abs(s) ** 2.2  # rows gathered about z = 0.5
    arc = np.gradient(np.unwrap(theta)) * radius
    step = np.gradient(z)
    area = np.abs(np.outer(step, arc)).ravel()
    th, zz = np.meshgrid(theta, z)
    x = np.stack(
        [centre[0] + radius * np.cos(th), centre[1] + radius * np.sin(th), zz], axis=-1
    ).reshape(-1, 3)
    pressure = 2000.0 * (1.0 + 0.5 * np.cos(th - 1.0) + 0.3 * (zz - 0.5)).ravel()
    return x, pressure * area, area, centre, radius


def by_hand(x, force, area, height, angle_deg, diameter, kernel):
    """A probe's reading written out: the footprint's radius, the band's nodes, their
    area-weighted centre, each node's distance on the body from the probe's centre and the
    kernel's weight, the weighted contact force over the weighted area."""
    radius = max(diameter / 2, math.sqrt(float(np.median(area))))
    weights_of = {
        "smooth": lambda s: np.where(np.abs(s) < 1, (1 - s * s) ** 2, 0.0),
        "hat": lambda s: np.where(np.abs(s) < 1, 1 - np.abs(s), 0.0),
    }[kernel]
    near = [i for i in range(len(x)) if abs(x[i, 2] - height) < radius]
    band = weights_of((x[near, 2] - height) / radius)
    centre = sum(area[i] * w * x[i, :2] for i, w in zip(near, band, strict=True)) / sum(
        area[i] * w for i, w in zip(near, band, strict=True)
    )
    top = bottom = 0.0
    for i in near:
        dx, dy = x[i, :2] - centre
        turn = math.atan2(dy, dx) - math.radians(angle_deg)
        turn = math.atan2(math.sin(turn), math.cos(turn))
        distance = math.hypot(x[i, 2] - height, math.hypot(dx, dy) * turn)
        weight = float(weights_of(np.array(distance / radius)))
        top += force[i] * weight
        bottom += area[i] * weight
    return top / bottom if bottom > 0 else float("nan")


#: Examples of each property: a bounded number in make test, more in make test-slow.
COUNTS = [pytest.param(25, id="25"), pytest.param(200, id="200", marks=pytest.mark.slow)]


def examples(count: int):
    """Hypothesis's settings for ``count`` examples, derandomised (the same ones each run)."""
    return settings(max_examples=count, deadline=None, derandomize=True, database=None)


@pytest.mark.parametrize("count", COUNTS)
def test_a_probe_reads_the_area_weighted_force_under_its_footprint(count):
    @examples(count)
    @given(
        seed=st.integers(0, 10_000),
        height=st.floats(0.40, 0.60),
        angle=st.floats(-180.0, 180.0),
        diameter=st.floats(0.01, 0.08),
        kernel=st.sampled_from(["smooth", "hat"]),
    )
    def rule(seed, height, angle, diameter, kernel):
        x, force, area, _, _ = gathered_tube(seed, 40, 25)
        reading = Reading(kernel=kernel)
        found = probe_readings(x, force, area, height, np.array([angle]), diameter, reading)[0]
        expected = by_hand(x, force, area, height, angle, diameter, kernel)
        assert found == pytest.approx(expected, rel=1e-9, nan_ok=True)

    rule()


def test_the_probe_s_centre_is_area_weighted_where_it_matters():
    """On the clustered tube the plain mean of the nodes is off the axis: a probe about it would
    read another place (the rule above fails a centre that is not area-weighted)."""
    x, _, area, centre, radius = gathered_tube(3, 40, 25)
    near = np.abs(x[:, 2] - 0.5) < 0.03
    plain = x[near, :2].mean(axis=0)
    weighted = (area[near] @ x[near, :2]) / area[near].sum()
    assert np.linalg.norm(weighted - centre) < 0.2 * np.linalg.norm(plain - centre)
    assert np.linalg.norm(plain - centre) > 0.01 * radius


@pytest.mark.parametrize("ratio", [2.0, 1.41, 1.7])
def test_every_level_is_at_least_the_smallest_grid_at_its_exact_threshold(ratio):
    """coarser_grids keeps a level of exactly `MIN_AROUND` x `MIN_ROWS` and refuses one node or
    one row fewer, at every ratio; each level is smaller than the one above in both."""
    for n in range(MIN_AROUND, 80):
        for m in range(MIN_ROWS, 40):
            levels = coarser_grids((n, m), 2, ratio)
            expected = []
            above = (n, m)
            for k in (1, 2):
                size = tuple(math.ceil(round(v / ratio**k, 9)) for v in (n, m))
                ok = size[0] >= MIN_AROUND and size[1] >= MIN_ROWS
                if not (ok and size[0] < above[0] and size[1] < above[1]):
                    break
                expected.append(size)
                above = size
            assert levels == expected, (n, m)
    exact = (2 * MIN_AROUND, 2 * MIN_ROWS)
    assert coarser_grids(exact, 1, 2.0) == [(MIN_AROUND, MIN_ROWS)]
    assert coarser_grids((exact[0] - 2, exact[1]), 1, 2.0) == []  # 7 around
    assert coarser_grids((exact[0], exact[1] - 2), 1, 2.0) == []  # 2 rows


def test_a_level_ratio_must_exceed_one():
    assert coarser_grids((64, 32), 1, 1.0 + 1e-9) == []  # not smaller: no level
    with pytest.raises(ValueError, match="exceed 1"):
        coarser_grids((64, 32), 1, 1.0)


@pytest.mark.parametrize(
    ("grid", "ok"),
    [([3, 2], True), ([2, 2], False), ([3, 1], False), ([4, 3], True)],
)
def test_the_smallest_grid_is_3_around_and_2_rows(grid, ok):
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": grid},
    }
    if ok:
        assert tuple(validate_case(case).garment.grid) == tuple(grid)
    else:
        with pytest.raises(InputError, match="grid"):
            validate_case(case)


def _tape_by_hull(mesh: trimesh.Trimesh, height: float, point) -> float | None:
    """The convex hull's perimeter (scipy) of the mesh's section loops (trimesh) at ``height``
    that enclose ``point`` (matplotlib's point-in-polygon); None where none does."""
    section = mesh.section(plane_origin=[0.0, 0.0, height], plane_normal=[0.0, 0.0, 1.0])
    loops = [loop[:, :2] for loop in section.discrete]
    inside = [loop for loop in loops if PolygonPath(loop).contains_point(point)]
    if not inside:
        return None
    return float(ConvexHull(np.concatenate(inside)).area)  # in 2-D, area is the perimeter


@pytest.mark.parametrize("name", sorted(p.stem for p in AVATARS.glob("*.json")))
def test_the_tape_girth_of_every_shipped_avatar_is_its_section_s_convex_hull(name):
    record = json.loads((AVATARS / f"{name}.json").read_text())
    mesh = trimesh.load(AVATARS / f"{name}.ply", process=False)
    body = MeshBody(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    point = record["loop_point_m"]
    checked = 0
    for line, girth in record["girths_m"].items():
        expected = _tape_by_hull(mesh, girth["height"], point)
        if expected is None:
            continue  # the leg's axis point is at mid-span: not inside at the ankle
        assert hull_girth(body, girth["height"], point) == pytest.approx(expected, abs=1e-6), line
        assert girth["avatar"] == pytest.approx(expected, abs=2e-6), line  # the record's
        checked += 1
    assert checked >= 4
