"""Figures framed to the body: each on-body view's box is the body's own aspect, so a leg fills
a tall panel and a torso a wide one; girth labels sit beside the body, not over it; class bands
are drawn only where the case judges a class; the interactive view's first camera frames the
whole garment and body. Checked on the parametric torso, the leg and a mesh body (a scanned
tube), at 1:1 in the figures as written."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import trimesh
import xarray as xr
from mpl_toolkits.mplot3d import proj3d

from cloth.figures.drawing import body_band, garment_positions
from cloth.figures.onbody import body_figure, drawn_share, framed_points
from cloth.figures.plots import class_bands
from cloth.figures.view import EYE_DISTANCE, scene_frame
from tests.conftest import load_result

#: Share of a view's panel (the figure's cell it was given) the body's projected bounding box
#: must fill: most of its height, and of its width what the girth labels beside it leave
#: (measured: torso 0.72 x 0.51-0.62, leg 0.9 x 0.48-0.53; a leg filled 0.47 of its height before).
HEIGHT_SHARE, WIDTH_SHARE = 0.7, 0.45


def _tube(folder: Path) -> str:
    mesh = trimesh.creation.cylinder(radius=0.09, height=0.7, sections=40)
    mesh.apply_translation([0.0, 0.0, 0.35])
    path = folder / "tube.obj"
    mesh.export(path)
    return str(path)


def _cases(folder: Path) -> dict[str, dict]:
    solver = {"method": "newton", "tolerance": 1.0e-8, "max_iterations": 150}
    common = {"reduction": 0.15, "edges": "sliding", "error_estimate": False}
    return {
        "torso": {
            "material": "powernet",
            "body": {"torso": {"size": "M"}},
            "garment": {"bottom": 0.86, "top": 1.22, "grid": [24, 12], **common},
            "solver": solver,
        },
        "leg": {
            "material": "powernet",
            "body": {"leg": {"size": "M"}},
            "garment": {
                "bottom": 0.09,
                "top": 0.77,
                "grid": [16, 24],
                "lengthwise_reduction": 0.15,
                **common,
            },
            "solver": solver,
        },
        "scan": {
            "material": "powernet",
            "body": {"mesh": _tube(folder), "surface": "mesh"},
            "landmarks": {"low": 0.2, "high": 0.5},
            "garment": {"bottom": 0.1, "top": 0.6, "grid": [20, 12], **common},
            "solver": solver,
        },
        # a band wider than tall (its box too, with the labels' room): the panel is made wide
        # enough that the body fills its height, as drawn (not the box, whose depth shows)
        "band": {
            "material": "powernet",
            "body": {"mesh": str(folder / "tube.obj"), "surface": "mesh"},
            "landmarks": {"mid": 0.36},
            "garment": {"bottom": 0.3, "top": 0.42, "grid": [20, 6], **common},
            "solver": solver,
        },
    }


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> dict[str, xr.Dataset]:
    folder = tmp_path_factory.mktemp("framing")
    return {name: load_result(folder / name, case) for name, case in _cases(folder).items()}


@pytest.mark.parametrize("name", ["torso", "leg", "scan", "band"])
def test_the_body_fills_its_panel_and_the_labels_sit_beside_it(results, name):
    ds = results[name]
    body = body_band(ds)
    fig = body_figure(ds, "body_pressure", body=body)
    fig.canvas.draw()
    fig.canvas.draw()  # constrained layout settles on the second draw, as savefig's
    points = framed_points(ds, body)
    views = [ax for ax in fig.axes if ax.name == "3d"]
    assert len(views) == 3
    for ax in views:
        height, width = drawn_share(ax, points)
        assert height >= HEIGHT_SHARE, (name, ax.get_title(), height)
        assert width >= WIDTH_SHARE, (name, ax.get_title(), width)
        # every girth label starts right of the body as drawn at its own height (beside it,
        # not over it): left-aligned at its anchor, projected as the view draws it
        x, y, _ = proj3d.proj_transform(*points.T, ax.get_proj())
        shown = ax.transData.transform(np.column_stack([x, y]))
        labels = [t for t in ax.texts if "mmHg" in t.get_text()]
        assert labels, name
        for text in labels:
            assert text.get_ha() == "left"
            tx, ty, _ = proj3d.proj_transform(*text.get_position_3d(), ax.get_proj())
            anchor = ax.transData.transform([[tx, ty]])[0]
            level = np.abs(shown[:, 1] - anchor[1]) <= 0.5 * text.get_fontsize()
            assert anchor[0] >= shown[level, 0].max() - 1.0, (name, text.get_text())
    plt.close(fig)


def test_a_legs_panels_are_tall_and_a_torsos_wide(results):
    shapes = {}
    for name in ("torso", "leg"):
        fig = body_figure(results[name], "body_pressure", body=body_band(results[name]))
        fig.canvas.draw()
        fig.canvas.draw()
        ax = next(a for a in fig.axes if a.name == "3d")
        cell = ax.get_position(original=True).transformed(fig.transFigure)
        shapes[name] = cell.height / cell.width
        plt.close(fig)
    assert shapes["leg"] > 1.5 > shapes["torso"], shapes
    fig = body_figure(results["band"], "body_pressure", body=body_band(results["band"]))
    fig.canvas.draw()
    fig.canvas.draw()
    ax = next(a for a in fig.axes if a.name == "3d")
    cell = ax.get_position(original=True).transformed(fig.transFigure)
    assert cell.height / cell.width < 0.82  # wider than tall: the fill, not the tall zoom
    plt.close(fig)


def test_class_bands_only_where_the_case_judges_a_class(results):
    """A stocking is judged at B (RAL-GZ 387/1 by default): its figures draw the classes; a
    torso or a scan has no class point, and its figures none."""
    assert [name for name, _, _ in class_bands(results["leg"])] == ["I", "II", "III"]
    assert class_bands(results["torso"]) == [] and class_bands(results["scan"]) == []


@pytest.mark.parametrize("name", ["torso", "leg", "scan"])
def test_the_first_camera_frames_the_whole_scene_at_one_scale(results, name):
    """One scale on every axis (the box's sides in proportion to the data's ranges, the
    longest 1), and the eye far enough to see the longest side whole."""
    ds = results[name]
    points = garment_positions(ds).reshape(-1, 3)
    frame = scene_frame(points)
    ratio = np.array([frame["aspectratio"][k] for k in "xyz"])
    ranges = np.ptp(points, axis=0)
    np.testing.assert_allclose(ratio, ranges / ranges.max(), rtol=1e-12)
    eye = frame["camera"]["eye"]
    assert np.hypot(eye["y"], eye["z"]) >= EYE_DISTANCE >= 1.5
