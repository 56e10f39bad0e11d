"""The numbers a user reads, against values written independently of the code: unit conversions
from their definitions, compression classes from the standard's table at both sides of every
band edge, girth-line means from closed forms and from the node fields by hand, design targets
in kPa and mmHg. Nothing here uses the code's own constants (`cloth.results.pressure.MMHG`, its
class tables), so a wrong constant fails a test.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.errors import InputError
from cloth.files.material import load_fabric
from cloth.pipeline.sweep import design, target_pa
from cloth.results.landmarks import Landmark, landmarks, nearest_row
from cloth.results.pressure import contact_reaction
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
#: 1 mmHg from its definition: mercury's conventional density 13.5951 g/cm3, standard gravity
#: 9.80665 m/s2, 1 mm: 133.322 Pa.
PA_PER_MMHG = 13.5951e3 * 9.80665 * 1e-3
#: RAL-GZ 387 classes, mmHg: class -> pressures just inside it (edges inclusive) ...
RAL = {"I": (18.0, 20.99), "II": (23.0, 32.0), "III": (34.0, 46.0), "IV": (49.0, 80.0)}
#: ... and pressures that are in no class (below I, between classes).
RAL_NONE = (0.0, 17.99, 21.01, 22.99, 32.01, 33.99, 46.01, 48.99)
#: Comfort groups of knitted garments, kPa, each [lower, upper): group -> pressures inside
#: (given to the summary as a case's pressure bands).
COMFORT = {"I": (0.4, 1.29), "II": (1.3, 1.99), "III": (2.0, 3.29), "IV": (3.3, 9.0)}


def test_one_mmhg_is_its_definition():
    assert PA_PER_MMHG == pytest.approx(133.322, abs=1e-3)
    row = Landmark("waist", 1.0, 3, 2666.45, 3000.0, 2000.0, 150.0).record()
    assert row["pressure_mean_mmHg"] == pytest.approx(2666.45 / PA_PER_MMHG, rel=1e-6)
    assert row["pressure_max_mmHg"] == pytest.approx(3000.0 / PA_PER_MMHG, rel=1e-6)
    assert row["pressure_min_mmHg"] == pytest.approx(2000.0 / PA_PER_MMHG, rel=1e-6)
    assert row["pressure_mean_kPa"] == pytest.approx(2.66645, rel=1e-12)


def _summary_row(
    tmp_path: Path, mmhg: float, line: str = "waist", judge: dict | None = None
) -> dict[str, str]:
    """The summary.csv row of a girth line ``line`` whose mean pressure is ``mmhg`` mmHg (with a
    case whose ``judge`` block is ``judge``, where given), through the writer users read
    (cloth.files.result)."""
    import json

    from cloth.case.case import validate_case
    from cloth.files.result import summary_rows, write_summary

    pa = mmhg * PA_PER_MMHG
    attrs: dict[str, object] = {"converged": 1}
    if judge is not None:
        case = {
            "material": "powernet",
            "body": {"cylinder": {"radius": 0.1}},
            "judge": judge,
            "garment": {"bottom": 0.1, "top": 0.4, "grid": [12, 6], "reduction": 0.2},
        }
        attrs["case"] = json.dumps(validate_case(case).to_dict())
    ds = xr.Dataset(
        {
            "landmark_height": ("landmark", [1.0]),
            "pressure_mean": ("landmark", [pa]),
            "pressure_max": ("landmark", [pa]),
            "pressure_min": ("landmark", [pa]),
            "tension_mean": ("landmark", [100.0]),
        },
        coords={"landmark": [line]},
        attrs=attrs,
    )
    path = tmp_path / f"summary_{mmhg}.csv"
    write_summary(summary_rows(ds, "case"), path)
    with open(path, newline="") as handle:
        return next(csv.DictReader(handle))


@pytest.mark.parametrize(
    ("mmhg", "expected"),
    [(p, name) for name, pair in RAL.items() for p in pair] + [(p, "-") for p in RAL_NONE],
)
def test_the_summary_gives_the_ral_class_at_b_of_the_mean_in_mmhg(tmp_path, mmhg, expected):
    row = _summary_row(tmp_path, mmhg, "B")
    assert row["compression_class"] == expected
    assert float(row["pressure_mean_mmHg"]) == pytest.approx(mmhg, abs=1e-4)
    assert float(row["pressure_mean_Pa"]) == pytest.approx(mmhg * 133.322, rel=1e-5)


def test_a_torso_line_gets_no_compression_class(tmp_path):
    """RAL-GZ 387/1 defines the classes at the ankle: a waist of 20 mmHg is judged by no
    class, and by no band unless the case defines some."""
    row = _summary_row(tmp_path, 20.0, "waist")
    assert "compression_class" not in row and "pressure_band" not in row
    assert not any("ral" in key.lower() or "comfort" in key for key in row)


@pytest.mark.parametrize(
    ("kpa", "expected"),
    [(p, name) for name, pair in COMFORT.items() for p in pair] + [(0.0, "-"), (0.39, "-")],
)
def test_bands_the_case_defines_judge_every_line(tmp_path, kpa, expected):
    """The comfort groups of knitted garments (kPa, [lower, upper)) given as the case's bands
    in mmHg: each line's band is the group its mean falls in."""
    edges = {"I": (0.4, 1.3), "II": (1.3, 2.0), "III": (2.0, 3.3), "IV": (3.3, 100.0)}
    bands = [
        {"name": name, "low_mmHg": low * 1000 / PA_PER_MMHG, "high_mmHg": high * 1000 / PA_PER_MMHG}
        for name, (low, high) in edges.items()
    ]
    row = _summary_row(tmp_path, kpa * 1000 / PA_PER_MMHG, "waist", {"bands": bands})
    assert row["pressure_band"] == expected
    assert float(row["pressure_mean_kPa"]) == pytest.approx(kpa, rel=1e-5)


def _run(
    tmp_path: Path, body: dict, garment: dict, landmarks: dict, extra: dict | None = None
) -> Path:
    case = {"material": "powernet", "body": body, "garment": garment, "landmarks": landmarks}
    case.update(extra or {})
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(case))
    run_case(path, tmp_path / "out", {}, ROOT, stop_after="aggregate")
    return tmp_path / "out"


def _probe_curvature(a: float, b: float, apex: float, radius: float) -> float:
    """The curvature of the ellipse (semi-axes a, b) averaged around the point at parameter
    ``apex`` with the biweight (1 - (s / radius)^2)^2 of the arc length s from it (quadrature
    in the parameter t, ds = sqrt(a^2 sin^2 t + b^2 cos^2 t) dt)."""
    t = apex + np.linspace(-0.6, 0.6, 20001)
    speed = np.sqrt(a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2)
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    arc -= np.interp(apex, t, arc)
    weight = np.where(np.abs(arc) < radius, (1 - (arc / radius) ** 2) ** 2, 0.0) * speed
    kappa = a * b / speed**3
    return float(np.trapezoid(weight * kappa, t) / np.trapezoid(weight, t))


def test_girth_line_pressures_on_an_ellipse_are_laplace_along_its_curvature(tmp_path):
    """A frictionless tube on an elliptic cylinder carries one hoop tension T all round; its
    pressure is T kappa, so along a girth line the mean is T 2 pi / L (the curvature of a closed
    convex curve integrates to 2 pi over its perimeter L); the largest and least readings of a
    5 cm probe are T kappa averaged over its footprint at the ends of the axes (about T a / b^2
    and T b / a^2). T is the lab curve's stress at the hoop strain 1 / (1 - reduction) - 1 times the
    thickness."""
    a, b, reduction = 0.12, 0.08, 0.15
    out = _run(
        tmp_path,
        {"elliptic_cylinder": {"a": a, "b": b, "bottom": 0.0, "top": 0.5}},
        {"bottom": 0.1, "top": 0.4, "reduction": reduction, "grid": [192, 7]},
        {"line": 0.25},
        {
            "sensors": [
                {"name": "end", "height": 0.25, "angle": 0},
                {"name": "side", "height": 0.25, "angle": 90},
            ]
        },
    )
    fabric = load_fabric("powernet", ROOT)
    strain = 1.0 / (1.0 - reduction) - 1.0
    tension = float(fabric.weft(np.array([strain]))[0]) * fabric.thickness  # N/m
    h = ((a - b) / (a + b)) ** 2
    perimeter = math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))  # Ramanujan
    with open(out / "summary.csv", newline="") as handle:
        row = next(csv.DictReader(handle))
    assert float(row["tension_weft_mean_N_per_m"]) == pytest.approx(tension, rel=5e-3)
    assert float(row["pressure_mean_Pa"]) == pytest.approx(
        2 * math.pi * tension / perimeter, rel=1e-2
    )
    # the max and min are a 5 cm probe's readings at the ends of the axes: Laplace's T kappa
    # averaged over its footprint along the girth with the biweight of the arc length
    assert float(row["pressure_max_Pa"]) == pytest.approx(
        tension * _probe_curvature(a, b, 0.0, 0.025), rel=1e-2
    )
    assert float(row["pressure_min_Pa"]) == pytest.approx(
        tension * _probe_curvature(a, b, math.pi / 2, 0.025), rel=1e-2
    )
    assert float(row["pressure_max_Pa"]) < tension * a / b**2  # the footprint averages the peak
    with xr.open_dataset(out / "result.nc") as ds:  # the per-node mmHg users map
        np.testing.assert_allclose(ds["pressure_mmHg"], ds["pressure"] / 133.322387, rtol=1e-8)
        assert (
            ds["pressure_mmHg"].attrs["units"] == "mmHg" and ds["pressure"].attrs["units"] == "Pa"
        )
        assert ds["tension_mean"].attrs["units"] == "N m-1"
        # sensors placed where the line's probe reads its max (angle 0) and min (90 degrees)
        sensed = dict(zip(ds["sensor"].values.tolist(), ds["sensor_pressure"].values, strict=True))
        assert sensed["end"] == pytest.approx(float(row["pressure_max_Pa"]), rel=1e-5)
        assert sensed["side"] == pytest.approx(float(row["pressure_min_Pa"]), rel=1e-5)
        assert ds["sensor_pressure"].attrs["units"] == "Pa"


def test_row_diagnostics_are_the_rows_interpolated_to_its_height_by_hand(tmp_path):
    """On a cone (every row its own radius, so its own pressure) each girth line's row
    diagnostics are the node pressures interpolated linearly in height between the rows around
    it, column by column (here by numpy's interp along each warp line): their mean, max and
    min. The band value lies between the rows around the line."""
    heights = {"low": 0.13, "mid": 0.24, "high": 0.37}
    out = _run(
        tmp_path,
        {"cone": {"radius_bottom": 0.13, "radius_top": 0.09, "bottom": 0.0, "top": 0.5}},
        {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [48, 12]},
        heights,
    )
    with xr.open_dataset(out / "result.nc") as ds:
        z, pressure = ds["z"].values, ds["pressure"].values  # (rows, cols)
        contact = ds["contact"].values.astype(bool)
        summary = {str(n): i for i, n in enumerate(ds["landmark"].values)}
        means = ds["row_pressure_mean"].values
        highest, lowest = ds["row_pressure_max"].values, ds["row_pressure_min"].values
        band = ds["pressure_mean"].values
    rows_z = z.mean(axis=1)
    on = np.where(contact, pressure, 0.0)
    seen = []
    for name, height in heights.items():
        line = np.array([np.interp(height, rows_z, on[:, i]) for i in range(on.shape[1])])
        i = summary[name]
        assert means[i] == pytest.approx(line.mean(), rel=1e-12)
        assert highest[i] == pytest.approx(line.max(), rel=1e-12)
        assert lowest[i] == pytest.approx(line.min(), rel=1e-12)
        below, above = np.searchsorted(rows_z, height) - 1, np.searchsorted(rows_z, height)
        rows = sorted([on[below].mean(), on[above].mean()])
        assert rows[0] - 1e-6 <= band[i] <= rows[1] + 1e-6
        seen.append(means[i])
    assert len({round(v, 3) for v in seen}) == 3  # the rows differ: the right ones are read


def _sweep(pressures_pa: list[float]) -> xr.Dataset:
    reductions = [0.1, 0.15, 0.2, 0.25]
    data = np.array(pressures_pa, float).reshape(1, 1, 4, 1)
    return xr.Dataset(
        {"pressure_mean": (("material", "body", "reduction", "landmark"), data)},
        coords={"material": ["m"], "body": ["b"], "reduction": reductions, "landmark": ["waist"]},
    )


def test_the_design_interval_is_the_stated_pressure_error_over_the_slope():
    """2000 Pa lies a quarter of the way from 1500 Pa (r 0.15, stated error 40 Pa) to 3500 Pa
    (r 0.25, 80 Pa): the error there is 50 Pa, the slope 20000 Pa per unit reduction, so the
    answer 0.175 holds to +- 0.0025; a case without an estimate gives no interval."""
    ds = xr.Dataset(
        {
            "pressure_mean": (
                ("material", "body", "reduction", "landmark"),
                np.array([1000.0, 1500.0, 3500.0]).reshape(1, 1, 3, 1),
            ),
            "pressure_mean_error": (
                ("material", "body", "reduction", "landmark"),
                np.array([30.0, 40.0, 80.0]).reshape(1, 1, 3, 1),
            ),
        },
        coords={
            "material": ["m"],
            "body": ["b"],
            "reduction": [0.1, 0.15, 0.25],
            "landmark": ["waist"],
        },
    )
    row = design(ds, [{"landmark": "waist", "pressure_kPa": 2.0}])[0]
    assert row["reduction"] == pytest.approx(0.175)
    assert row["reduction_error"] == pytest.approx(0.0025)
    assert row["slope_Pa"] == pytest.approx(20000.0)  # (3500 - 1500) / (0.25 - 0.15)
    assert (row["reduction_low"], row["reduction_high"]) == pytest.approx((0.1725, 0.1775))
    ds["pressure_mean_error"][0, 0, 2, 0] = np.nan
    row = design(ds, [{"landmark": "waist", "pressure_kPa": 2.0}])[0]
    assert math.isnan(row["reduction_error"])


def test_design_targets_in_kpa_and_in_mmhg_give_the_same_reduction():
    """A target of 2 kPa and one of 2000 / 133.322 mmHg are the same pressure: the same
    reduction, read off the sweep by hand (2000 Pa lies halfway between 1500 and 2500 Pa)."""
    ds = _sweep([1000.0, 1500.0, 2500.0, 3500.0])
    kpa = design(ds, [{"landmark": "waist", "pressure_kPa": 2.0}])[0]
    mmhg = design(ds, [{"landmark": "waist", "pressure_mmHg": 2000.0 / PA_PER_MMHG}])[0]
    assert kpa["status"] == mmhg["status"] == "ok"
    assert kpa["reduction"] == pytest.approx(0.175, abs=1e-9)
    assert mmhg["reduction"] == pytest.approx(0.175, abs=1e-6)
    assert kpa["target_Pa"] == pytest.approx(2000.0) and kpa["target_mmHg"] == pytest.approx(
        2000.0 / PA_PER_MMHG, rel=1e-6
    )
    assert target_pa({"pressure_kPa": 3.5}) == pytest.approx(3500.0)
    assert target_pa({"pressure_mmHg": 20}) == pytest.approx(20 * PA_PER_MMHG, rel=1e-6)


def test_a_design_row_says_what_it_found_in_its_own_words():
    """ok at the sweep's ends too; two finite points are enough; outside, the range in mmHg by
    hand (1000-3500 Pa is 7.50-26.3 mmHg); one point is no data; an unknown line is refused."""
    ds = _sweep([1000.0, 1500.0, 2500.0, 3500.0])
    for pa, reduction in ((1000.0, 0.1), (3500.0, 0.25)):
        row = design(ds, [{"landmark": "waist", "pressure_kPa": pa / 1000}])[0]
        assert (row["status"], row["message"]) == ("ok", "")
        assert row["reduction"] == pytest.approx(reduction)
    assert set(row) == {
        "material",
        "body",
        "landmark",
        "target_Pa",
        "target_mmHg",
        "reduction",
        "slope_Pa",
        "reduction_error",
        "reduction_low",
        "reduction_high",
        "status",
        "message",
    }
    assert (row["material"], row["body"], row["landmark"]) == ("m", "b", "waist")
    two = design(
        _sweep([math.nan, 1500.0, 2500.0, math.nan]), [{"landmark": "waist", "pressure_kPa": 2.0}]
    )[0]
    assert two["status"] == "ok" and two["reduction"] == pytest.approx(0.175)
    high = design(ds, [{"landmark": "waist", "pressure_kPa": 5.0}])[0]
    assert high["status"] == "out_of_range" and math.isnan(high["reduction"])
    assert "reaches 37.5 mmHg at the waist" in high["message"]
    assert "the sweep gives 7.5-26.3 mmHg" in high["message"]
    one = design(
        _sweep([math.nan, 1500.0, math.nan, math.nan]), [{"landmark": "waist", "pressure_kPa": 2.0}]
    )[0]
    assert one["status"] == "no_data" and one["message"] == "fewer than two swept reductions"
    with pytest.raises(InputError) as error:
        design(ds, [{"landmark": "hip", "pressure_kPa": 2.0}])
    assert error.value.field == "targets" and "the sweep has waist" in str(error.value)


class _Fields:
    """Node fields of a 4 x 3 grid (rows at 0.1, 0.2, 0.3 m): pressure (Pa) 100 x row + node,
    the last node of each row off the body, every node's area 1 m2 but the first row's 2 m2."""

    def __init__(self) -> None:
        self.pressure = np.array([100.0 * r + i for r in range(3) for i in range(4)])
        self.on_body = np.array([1, 1, 1, 0] * 3, np.int8)
        self.tension_weft = np.full(12, 50.0)
        self.area = np.array([2.0] * 4 + [1.0] * 8)


def test_row_diagnostics_read_the_rows_bottom_to_top_and_count_the_off_body_as_zero():
    grid = SimpleNamespace(m=3, n=4)
    x = np.array([[0.0, 0.0, z] for z in (0.1, 0.2, 0.3) for _ in range(4)])
    heights = {"bust": 0.34, "below": 0.04, "waist": 0.21, "hip": 0.05, "above": 0.36}
    marks = landmarks(heights, x, _Fields(), grid)
    assert [m.name for m in marks] == ["hip", "waist", "bust"]  # by height; half a row out
    assert [m.row for m in marks] == [0, 1, 2]
    mid = marks[1]  # the waist
    # 0.21 m: a tenth of the way from the row at 0.2 m to the one at 0.3 m, column by column
    expected = ((110 + 111 + 112 + 0) / 4, 112, 0)
    assert (mid.row_mean, mid.row_max, mid.row_min) == pytest.approx(expected)
    assert mid.tension == pytest.approx(50.0) and mid.height == 0.21
    row = mid.record()
    assert row["height_m"] == 0.21 and row["landmark"] == "waist" and row["row"] == 1
    assert nearest_row(np.array([0.2]), 0.2) == 0 and nearest_row(np.array([0.2]), 0.2001) is None
    assert nearest_row(np.array([0.1, 0.2]), 0.24) == 1  # two rows: half a spacing beyond


#: The band kernels K(s), s the height from the line over the half width (docs/outputs.md):
#: the biweight and the hat, typed here.
KERNELS = {
    "smooth": lambda s: max(0.0, 1 - s * s) ** 2,
    "hat": lambda s: max(0.0, 1 - abs(s)),
}


def _kernel_share(
    low: float, high: float, height: float, half: float = 0.02, kernel: str = "smooth"
) -> float:
    """The integral of the kernel K((z - height) / half) over [low, high], m."""
    from scipy.integrate import quad

    shape = KERNELS[kernel]
    return quad(
        lambda z: shape((z - height) / half),
        low,
        high,
        points=[height - half, height, height + half],
    )[0]


@pytest.mark.parametrize("kernel", sorted(KERNELS))
@pytest.mark.parametrize("height", [0.155, 0.21, 0.245, 0.29])
def test_band_values_weigh_each_node_by_the_kernel_over_its_span_of_height(height, kernel):
    """The band mean is sum f_i w_i / sum a_i w_i with f_i = p_i a_i and w_i the kernel
    (``smooth``, the biweight, and ``hat``) integrated over the node's span (half-way to its
    warp neighbours: 0.1-0.15, 0.15-0.25, 0.25-0.3 m) over the span's length, here by scipy's
    quad: 0.245 m straddles two rows' spans, 0.155 m the first row's (2 m2 a node) and the
    second's (1 m2), 0.29 m is clipped at the garment's top edge."""
    from cloth.case.reading import Reading

    grid = SimpleNamespace(m=3, n=4)
    x = np.array([[0.0, 0.0, z] for z in (0.1, 0.2, 0.3) for _ in range(4)])
    fields = _Fields()
    spans = [(0.1, 0.15), (0.15, 0.25), (0.25, 0.3)]
    share = [_kernel_share(lo, hi, height, kernel=kernel) / (hi - lo) for lo, hi in spans]
    w = np.repeat(share, 4)
    force = np.where(fields.on_body == 1, fields.pressure, 0.0) * fields.area
    (mark,) = landmarks({"line": height}, x, fields, grid, Reading(kernel=kernel))
    assert mark.mean == pytest.approx(np.sum(force * w) / np.sum(fields.area * w), rel=1e-10)
    assert mark.tension == pytest.approx(50.0, rel=1e-12)


def test_the_bodys_reaction_balances_what_the_springs_leave_on_a_held_node():
    """A held node pulled inward by 5 N of springs with 1 N of it left unbalanced (the part the
    body does not carry) gets 4 N outward from the body; a free node gets none."""
    forces = np.array([[0.0, 0.0, -5.0], [1.0, 0.0, 0.0]])
    unbalanced = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    reaction = contact_reaction(forces, unbalanced, np.array([True, False]))
    np.testing.assert_array_equal(reaction, [[0.0, 0.0, 4.0], [0.0, 0.0, 0.0]])


@pytest.mark.parametrize(
    ("c_mmhg", "met"),
    [(21.0, 1), (15.0, 0), (28.5, 0), (18.0, 1), (24.0, 1)],
    ids=["inside", "below", "above", "at-low", "at-high"],
)
def test_graduation_is_met_inside_its_limits_only(c_mmhg, met):
    """A point's graduation is met where its share of the class point's pressure lies within
    its limits (ends included), not outside; a line without limits is left blank."""
    from cloth.case.judge import Judge
    from cloth.results.judging import judged

    judge = Judge.from_block({"graduation": {"C": [0.6, 0.8]}})
    rows = [
        {"landmark": "B", "pressure_mean_mmHg": 30.0},
        {"landmark": "C", "pressure_mean_mmHg": c_mmhg},
        {"landmark": "waist", "pressure_mean_mmHg": 10.0},
    ]
    b, c, other = judged(rows, judge)
    assert c["share_of_class_point"] == c_mmhg / 30.0  # 18 / 30 is the float 0.6: ends exact
    assert c["graduation_met"] == met
    assert other["graduation_met"] == "" and b["compression_class"] == "II"


def test_every_judging_column_of_every_row():
    """The class on the class point's row only (blank on the others), the share of the class
    point's pressure (NaN where that is 0; computed where it is just above 0), the limits of
    each point with limits and blanks for a line without them."""
    from cloth.case.judge import Judge
    from cloth.results.judging import judged

    judge = Judge.from_block({"graduation": {"C": [0.6, 0.8]}})
    rows = [
        {"landmark": "B", "pressure_mean_mmHg": 0.5},
        {"landmark": "C", "pressure_mean_mmHg": 0.35},
        {"landmark": "waist", "pressure_mean_mmHg": 0.1},
    ]
    b, c, waist = judged(rows, judge)
    assert (b["compression_class"], c["compression_class"], waist["compression_class"]) == (
        "-",
        "",
        "",
    )
    assert c["share_of_class_point"] == 0.35 / 0.5 and waist["share_of_class_point"] == 0.2
    assert (c["graduation_low"], c["graduation_high"], c["graduation_met"]) == (0.6, 0.8, 1)
    for row in (b, waist):
        assert (row["graduation_low"], row["graduation_high"], row["graduation_met"]) == (
            "",
            "",
            "",
        )
    assert "pressure_band" not in b  # the case defines no bands
    zero = judged([{"landmark": "B", "pressure_mean_mmHg": 0.0}, rows[1]], judge)
    assert np.isnan(zero[1]["share_of_class_point"])


@pytest.mark.parametrize(
    ("height", "expected"),
    [
        (0.10, (0, 0, 0.0)),  # exactly the bottom row
        (0.08, (0, 0, 0.0)),  # below it, within half a row spacing
        (0.04, None),  # beyond that: not on the garment
        (0.30, (2, 2, 0.0)),  # exactly the top row
        (0.33, (2, 2, 0.0)),
        (0.36, None),
        (0.15, (0, 1, 0.5)),
        (0.25, (1, 2, 0.5)),
        (0.20, (1, 2, 0.0)),  # exactly an inner row: the weight of the row above is 0
    ],
)
def test_a_girth_line_lies_between_its_rows_or_on_an_edge_row(height, expected):
    """Rows at 0.1, 0.2, 0.3 m: the line's rows and the upper one's weight by hand."""
    from cloth.results.landmarks import girth_line

    line = girth_line(np.array([0.1, 0.2, 0.3]), height)
    if expected is None:
        assert line is None
    else:
        assert line[:2] == expected[:2] and line[2] == pytest.approx(expected[2], abs=1e-12)


@pytest.mark.parametrize(
    ("mmhg", "name"),
    [(18.0, "I"), (21.0, "I"), (22.0, "-"), (23.0, "II"), (32.0, "II"), (49.0, "IV"), (17.9, "-")],
)
def test_a_class_edge_belongs_to_its_class(mmhg, name):
    """RAL-GZ 387/1's limits, typed here: I 18-21, II 23-32, III 34-46, IV from 49 mmHg; both
    limits inside their class, the gaps between classes in none."""
    from cloth.results.pressure import ral_class

    assert ral_class(mmhg) == name


@pytest.mark.parametrize(
    ("kpa", "name"),
    [(0.4, "I"), (1.3, "II"), (1.2999, "I"), (2.0, "III"), (3.3, "IV"), (0.39, "-")],
)
def test_a_comfort_group_starts_at_its_lower_limit(kpa, name):
    """Comfort groups, kPa (typed here): I 0.4-1.3, II 1.3-2.0, III 2.0-3.3, IV from 3.3; each
    includes its lower limit only, and below group I there is none ('-')."""
    from cloth.results.pressure import comfort_group

    assert comfort_group(kpa) == name
