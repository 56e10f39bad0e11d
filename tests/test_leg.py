"""The parametric leg (issue 31, items 1-2): the chart's girths at the measuring points, a C2
profile without overshoot, bad charts refused in one line, and a stocking on a circular leg
against Laplace."""

from __future__ import annotations

import itertools
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from cloth.bodies.leg import POINTS, SmoothLeg, _profiles, leg_mesh, leg_size
from cloth.results.pressure import MMHG
from tests.conftest import load_result

ROOT = Path(__file__).resolve().parents[1]
CHART = ROOT / "data" / "bodies" / "leg_chart.csv"


def perimeter(points: np.ndarray) -> float:
    """The length of the closed polygon through ``points`` ((K, 2) or (K, 3), m), the closing
    edge included: measured here, not with the builder's own `perimeter`, so that a builder
    scaling its sections with a wrong measure (an open polygon) is caught."""
    closed = np.vstack([points, points[:1]])
    return float(np.sum(np.hypot(*np.diff(closed[:, :2], axis=0).T)))


@pytest.mark.parametrize("size", ["S", "M", "L"])
def test_girths_at_the_measuring_points_are_the_chart_s(size):
    """On the smooth surface (a 4096-gon of its section) and on the mesh's ring there: within
    0.5 mm of the chart (measured: 0.3 um on the surface)."""
    chart = leg_size(size)
    body = SmoothLeg(chart)
    vertices, _ = leg_mesh(chart, 96, 160)
    for point in POINTS:
        z = chart.height[point]
        assert perimeter(body._polygon(z)) == pytest.approx(chart.girth[point], abs=5e-4)
        ring = vertices[np.isclose(vertices[:, 2], z, atol=1e-12)]
        order = np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))
        assert perimeter(ring[order, :2]) == pytest.approx(chart.girth[point], abs=5e-4)


def test_the_profile_is_c2_across_the_points_where_pchip_is_not():
    """The girth's second derivative from either side of every measuring point agrees to 1e-6
    of its scale; PCHIP's (the torso's profile) jumps there by more than that at most points."""
    chart = leg_size("M")
    girth = _profiles(chart)[0]
    second = girth.derivative(2)
    z = np.array([chart.height[p] for p in POINTS])
    scale = float(np.max(np.abs(second(np.linspace(chart.bottom, chart.top, 2001)))))
    jumps = np.abs(second(z + 1e-9) - second(z - 1e-9))
    assert np.all(jumps <= 1e-6 * scale), jumps / scale
    knots = [chart.bottom, *z, chart.top]
    values = girth(knots)
    pchip = PchipInterpolator(knots, values).derivative(2)
    assert np.sum(np.abs(pchip(z + 1e-9) - pchip(z - 1e-9)) > 1e-3 * scale) >= 4


def test_between_two_points_the_girth_stays_between_theirs():
    """No overshoot: on every stretch between neighbouring points the girth lies within their
    values (to 1e-9 m)."""
    for size in ("S", "M", "L"):
        chart = leg_size(size)
        girth = _profiles(chart)[0]
        z = [chart.bottom, *(chart.height[p] for p in POINTS), chart.top]
        for low, high in itertools.pairwise(z):
            values = girth(np.linspace(low, high, 200))
            ends = girth([low, high])
            assert values.min() >= ends.min() - 1e-9 and values.max() <= ends.max() + 1e-9


def _bad_chart(folder: Path, change) -> Path:
    lines = CHART.read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("size,"))
    columns = lines[header].split(",")
    row = dict(zip(columns, lines[header + 2].split(","), strict=True))  # size M
    change(row)
    path = folder / "bad.csv"
    path.write_text("\n".join([lines[header], ",".join(row.get(c, "") for c in columns)]) + "\n")
    return path


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (lambda row: row.update(D_cm=""), "size M, point D"),
        (lambda row: row.update(D_height_cm="30"), "size M, point D"),
        (lambda row: row.update(F_cm="0"), "size M, point F"),
        (lambda row: row.update(C_cm="inf"), "size M, point C"),
        (lambda row: row.update(D_height_cm="nan"), "size M, point D"),
    ],
    ids=[
        "missing point",
        "non-monotone height",
        "zero circumference",
        "infinite circumference",
        "nan height",
    ],
)
def test_a_bad_chart_is_one_line_naming_the_size_and_the_point(tmp_path, change, words):
    chart = _bad_chart(tmp_path, change)
    output = tmp_path / "leg.ply"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "cloth",
            "body",
            "leg",
            "--size",
            "M",
            "--chart",
            str(chart),
            "-o",
            str(output),
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cloth: error: ") and words in lines[0]
    assert not output.exists()


def test_a_stocking_on_a_circular_leg_is_laplace_row_by_row(tmp_path):
    """A leg of circular sections (depth ratio 1), a graded tube at a constant reduction of 0.25,
    pulled up by a lengthwise reduction of 0.15 (which holds the rows: without it they slide
    down towards the ankle). Away from the ends each row's pressure is Laplace's for a surface
    of revolution, with the radius r(z) of the leg's own profile (not the garment's geometry):
    T_weft cos(alpha) / (r (1 + eps_warp)) + T_warp kappa_meridian / (1 + eps_weft), within 1 %.
    At B and at F the hoop's share of the pressure per unit hoop tension is cos(alpha) / r: their
    ratio is the radius ratio (2.3) within 1 %. 48 x 80: at 48 x 40 two rows near the knee miss
    by 1.2 % (the warp's curvature from three rows 1.7 cm apart over a profile that bends
    within 5 cm)."""
    text = CHART.read_text()
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    rows = [dict(zip(header, line.split(","), strict=True)) for line in lines[1:]]
    for row in rows:
        row.update({f"{p}_depth_ratio": "1" for p in POINTS})
    chart = tmp_path / "round.csv"
    chart.write_text("\n".join([lines[0], *(",".join(r[c] for c in header) for r in rows)]))
    case = {
        "material": "powernet",
        "body": {"leg": {"size": "M", "chart": str(chart)}},
        "garment": {
            "bottom": 0.09,
            "top": 0.75,
            "grid": [48, 80],
            "reduction": 0.25,
            "lengthwise_reduction": 0.15,
            "error_estimate": False,
        },
    }
    ds = load_result(tmp_path / "run", case)
    assert ds.attrs["converged"] == 1
    girth = _profiles(leg_size("M", chart))[0]
    z = ds["z"].values.mean(axis=1)
    r = girth(z) / (2 * np.pi)
    slope = girth.derivative(1)(z) / (2 * np.pi)
    bend = girth.derivative(2)(z) / (2 * np.pi)
    cos_alpha = 1.0 / np.sqrt(1.0 + slope**2)
    meridian = -bend / (1.0 + slope**2) ** 1.5
    mean = {
        k: ds[k].values.mean(axis=1)
        for k in ("tension_weft", "tension_warp", "strain_weft", "strain_warp", "pressure")
    }
    laplace = mean["tension_weft"] * cos_alpha / (r * (1 + mean["strain_warp"])) + mean[
        "tension_warp"
    ] * meridian / (1 + mean["strain_weft"])
    inner = slice(3, -3)
    np.testing.assert_allclose(mean["pressure"][inner], laplace[inner], rtol=1e-2)
    # Laplace's 1/r: the hoop's share of the pressure per unit hoop tension, at B and at F
    warp = mean["tension_warp"] * meridian / (1 + mean["strain_weft"])
    per_tension = (mean["pressure"] - warp) * (1 + mean["strain_warp"]) / mean["tension_weft"]
    b, f = (int(np.argmin(np.abs(z - h))) for h in (0.11, 0.64))
    ratio = (per_tension[b] / per_tension[f]) / ((cos_alpha[b] / r[b]) / (cos_alpha[f] / r[f]))
    assert ratio == pytest.approx(1.0, rel=1e-2)
    assert r[f] / r[b] > 2  # the thigh is more than twice the ankle
    assert mean["pressure"][b] / MMHG > mean["pressure"][f] / MMHG  # graduated


def test_a_leg_given_point_by_point_is_the_chart_s_leg(tmp_path):
    """Circumferences and heights at every point (no size) build the leg of those values; one
    point left out is one line naming it; a size with one point over it changes that point."""
    from cloth.bodies.leg import leg_of
    from cloth.errors import InputError

    m = leg_size("M")
    given = {
        "circumference_cm": {p: 100 * m.girth[p] for p in POINTS},
        "height_cm": {p: 100 * m.height[p] for p in POINTS},
    }
    leg = leg_of(given)
    assert leg.girth == pytest.approx(m.girth) and leg.height == pytest.approx(m.height)
    assert SmoothLeg(leg).girth(m.height["C"])[0] == pytest.approx(m.girth["C"], abs=1e-9)
    del given["circumference_cm"]["F"]
    with pytest.raises(InputError, match="point F"):
        leg_of(given)
    wider = leg_of({"size": "M", "circumference_cm": {"C": 40.0}})
    assert wider.girth["C"] == pytest.approx(0.40) and wider.girth["B"] == m.girth["B"]


def test_a_leaning_leg_has_exact_derivatives_and_the_chart_s_girths():
    """A leg leaning 8 degrees forward: the implicit function's gradient and Hessian equal
    central differences, closest points are feet of the normal, and the horizontal sections'
    girths at the points are still the chart's."""
    chart = leg_size("M")
    leg = SmoothLeg(chart, 8.0)
    z = np.linspace(chart.bottom + 0.01, chart.top - 0.01, 60)
    angle = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    rng = np.random.default_rng(3)
    p = np.column_stack([0.12 * np.cos(angle), 0.12 * np.sin(angle), z])
    p[:, 1] += np.tan(np.radians(8.0)) * (z - chart.height["B"]) + rng.normal(0, 0.005, 60)
    q = leg.closest(p)
    assert np.abs(leg.implicit(q)[0]).max() <= 1e-10
    _, g, h = leg.implicit(q)
    step = 1e-6
    for axis in range(3):
        dq = np.zeros(3)
        dq[axis] = step
        plus, minus = leg.implicit(q + dq), leg.implicit(q - dq)
        np.testing.assert_allclose(
            g[:, axis], (plus[0] - minus[0]) / (2 * step), atol=1e-6 * np.abs(g).max()
        )
        np.testing.assert_allclose(
            h[:, :, axis], (plus[1] - minus[1]) / (2 * step), atol=1e-6 * np.abs(h).max()
        )
    normal = g / np.linalg.norm(g, axis=1, keepdims=True)
    along = p - q
    np.testing.assert_allclose(np.cross(along, normal), 0.0, atol=1e-9)
    for point in POINTS:
        section = leg._polygon(chart.height[point])
        assert perimeter(section) == pytest.approx(chart.girth[point], abs=5e-4)
    centre = leg._polygon(chart.height["G"]).mean(axis=0)
    lean = np.tan(np.radians(8.0)) * (chart.height["G"] - chart.height["B"])
    assert centre[1] == pytest.approx(lean, abs=1e-3)


def test_a_leaning_leg_pivots_at_the_ankle_on_the_surface_and_the_mesh():
    """The lean turns the leg about B: B's section stays where the upright leg has it, and G's
    moves forward by tan(lean) (G - B), on the smooth surface and on the mesh alike."""
    chart = leg_size("M")
    slope = np.tan(np.radians(8.0))
    upright, leaning = SmoothLeg(chart), SmoothLeg(chart, 8.0)
    vertices, _ = leg_mesh(chart, 96, 160, 8.0)
    flat, _ = leg_mesh(chart, 96, 160)
    for point in ("B", "C", "G"):
        z = chart.height[point]
        shift = slope * (z - chart.height["B"])
        moved = leaning._polygon(z).mean(axis=0) - upright._polygon(z).mean(axis=0)
        np.testing.assert_allclose(moved, [0.0, shift], atol=1e-6)
        ring = vertices[np.isclose(vertices[:, 2], z, atol=1e-12)]
        ring0 = flat[np.isclose(flat[:, 2], z, atol=1e-12)]
        np.testing.assert_allclose(
            ring[:, :2].mean(axis=0) - ring0[:, :2].mean(axis=0), [0.0, shift], atol=1e-6
        )
