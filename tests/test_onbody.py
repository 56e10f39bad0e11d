"""Figures on the body: the garment's quads over the body's triangles in three views, on a torso,
a cylinder and a mesh body, with the colours, girth labels and colour bar of the result."""

from __future__ import annotations

import numpy as np
import pytest
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from cloth.bodies.torso import chart_size, torso_mesh
from cloth.figures.drawing import body_band
from cloth.figures.onbody import (
    FIELDS,
    VIEWS,
    body_figure,
    visible_quads,
)
from cloth.figures.plots import FIGURES
from cloth.figures.ranges import field_range, shared_ranges
from cloth.results.pressure import MMHG
from cloth.stages.case import initial_state
from cloth.stages.results import aggregate
from tests.conftest import write_obj
from tests.test_relax import solve
from tests.test_results import relaxed_file

BODIES = {
    "torso": ({"torso": {"size": "M"}}, 0.95, 1.10),
    "cylinder": ({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.15, 0.35),
    # faceted contact: the figure draws the mesh either way, and the fit would take 20 s
    "mesh": ({"mesh": "torso.obj", "surface": "mesh"}, 0.95, 1.10),
}


@pytest.fixture(scope="module", params=sorted(BODIES))
def result(request, tmp_path_factory):
    tmp = tmp_path_factory.mktemp(request.param)
    body, bottom, top = BODIES[request.param]
    if "mesh" in body:
        body = {**body, "mesh": str(tmp / body["mesh"])}
    write_obj(tmp / "torso.obj", *torso_mesh(chart_size("M"), 64, 60))
    case = {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": bottom,
            "top": top,
            "reduction": 0.15,
            "grid": [32, 6],
            "edges": "sliding",
        },
    }
    state = initial_state(case, tmp)
    iterations = 8 if request.param == "mesh" else 60  # faceted: converged or not, it draws
    path = relaxed_file(tmp, state, solve(state, tolerance=1e-8, iterations=iterations))
    return request.param, aggregate(path)[0]


def _collections(ax, gid):
    return [c for c in ax.collections if isinstance(c, Poly3DCollection) and c.get_gid() == gid]


def test_the_figure_holds_the_body_and_the_garment_in_three_views(result):
    kind, ds = result
    assert set(FIELDS) <= set(FIGURES)
    body = body_band(ds)
    assert body is not None and len(body[1]) > 50
    fig = body_figure(ds, "body_pressure", body=body)
    views = [ax for ax in fig.axes if hasattr(ax, "get_zlim")]
    assert [ax.get_title() for ax in views] == list(VIEWS)
    for ax in views:
        (garment,) = _collections(ax, "garment")
        (skin,) = _collections(ax, "body")
        assert len(garment.get_facecolors()) > 20 and len(skin.get_facecolors()) > 10
    # each view shows the side facing it: the front +y, the side +x, the back -y
    points = np.stack([ds[c].values for c in "xyz"], axis=-1).reshape(-1, 3)
    axis = points.mean(axis=0)
    for view, azimuth in VIEWS.items():
        quads, values = visible_quads(ds, "pressure_mmHg", 1.0, azimuth)
        eye = [np.cos(np.radians(azimuth)), np.sin(np.radians(azimuth)), 0]
        towards, radius = (quads.mean(axis=1) - axis) @ eye, np.ptp(points @ eye) / 2
        assert towards.min() > -0.3 * radius and towards.mean() > 0.4 * radius, view
        assert values.min() >= float(ds["pressure_mmHg"].min()) - 1e-12
    bars = [ax for ax in fig.axes if ax.get_ylabel() == "pressure [mmHg]"]
    assert len(bars) == 1
    labels = [t.get_text() for ax in views for t in ax.texts]
    for index, name in enumerate(ds["landmark"].values.tolist()):
        mean = float(ds["pressure_mean"][index]) / MMHG
        if any(t.startswith(f"{name} ") for t in labels):
            assert f"{name} {mean:.3g} mmHg" in labels
    assert any("mmHg" in t for t in labels) or kind == "cylinder"


@pytest.mark.parametrize("result", ["cylinder"], indirect=True)
def test_the_cylinders_body_is_its_surface_and_the_quads_carry_the_corner_means(result):
    _, ds = result
    vertices, _ = body_band(ds)
    np.testing.assert_allclose(np.hypot(vertices[:, 0], vertices[:, 1]), 0.1, rtol=1e-12)
    assert np.hypot(ds["x"].values, ds["y"].values).min() > 0.1 - 1e-6
    p = ds["pressure_mmHg"].values
    corners = (
        p[:-1, :-1]
        + np.roll(p, -1, axis=1)[:-1, :-1]
        + p[1:, :-1]
        + np.roll(p, -1, axis=1)[1:, :-1]
    ) / 4
    quads, values = visible_quads(ds, "pressure_mmHg", 1.0, 0.0)
    assert len(quads) >= corners.size / 3
    assert np.all(np.min(np.abs(values[:, None] - corners.ravel()[None]), axis=1) < 1e-12)
    assert field_range([ds], "pressure_mmHg") == (0.0, pytest.approx(np.percentile(p, 95)))


def test_a_sweeps_figures_share_one_colour_range(tmp_path):
    from tests.test_relax import tube

    results = []
    for reduction in (0.1, 0.2):
        state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, reduction, 24, 4)
        results.append(aggregate(relaxed_file(tmp_path, state, solve(state)))[0])
    low, high = results[0]["pressure_mmHg"], results[1]["pressure_mmHg"]
    assert float(high.median()) > 2 * float(low.median())  # Laplace: tighter presses harder
    forward, backward = shared_ranges(results), shared_ranges(results[::-1])
    assert forward == backward
    (s_low, s_high), (p_low, p_high) = forward
    # the range is the 95th percentile of all maps, to rounding (a uniform map: equal values)
    assert p_low == 0.0 and p_high >= float(np.percentile(high, 95)) * (1 - 1e-12)
    top = float(np.percentile(results[1]["stress_weft"], 95))
    assert s_low <= 0.0 < top <= s_high * (1 + 1e-12)


def test_the_body_drawn_around_a_garment_on_a_full_body_leaves_the_arms_out():
    """body_band: the body from below to above the garment and around it (8 cm): on a full
    body in its A-pose (1.05 m from hand to hand) a band at 0.9-1.2 m keeps the trunk only, so
    the garment, not the arm span, frames the figure."""
    import json
    from pathlib import Path

    import numpy as np
    import xarray as xr

    from cloth.figures.drawing import BODY_MARGIN, body_band
    from cloth.io import sha256

    scan = Path(__file__).parent / "data" / "full_body_mm_yup.ply"
    angle = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    z = np.linspace(0.9, 1.2, 5)
    shape = (len(z), len(angle))
    ring = {"x": 0.15 * np.cos(angle), "y": 0.11 * np.sin(angle) + 0.02}
    coords = {k: (("row", "col"), np.broadcast_to(v, shape)) for k, v in ring.items()}
    coords["z"] = (("row", "col"), np.broadcast_to(z[:, None], shape))
    block = {"mesh": str(scan), "units": "mm", "up": "y"}
    record = {"block": block, "kind": "mesh", "path": str(scan), "sha256": sha256(scan)}
    ds = xr.Dataset(coords, attrs={"body": json.dumps(record)})
    vertices, faces = body_band(ds)
    assert len(faces) > 500
    assert vertices[:, 0].max() <= 0.15 + BODY_MARGIN + 1e-9  # not the hands at 0.53 m
    assert vertices[:, 2].min() >= 0.9 - BODY_MARGIN and vertices[:, 2].max() <= 1.2 + BODY_MARGIN
