"""The worn garment: rest lengths longer by the set strain, the curve from the set length."""

from __future__ import annotations

import numpy as np
import pytest

from cloth.errors import InputError
from cloth.files.body import body_from_config
from cloth.garment.grid import node_area
from cloth.materials.labtables import ingest
from cloth.results.pressure import contact_reaction
from cloth.solvers import Settings, relax
from cloth.stages.case import initial_state

CYLINDER = {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}


def tube(reduction, material="powernet", **garment):
    return {
        "material": material,
        "body": CYLINDER,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": reduction,
            "grid": [64, 4],
            "edges": "sliding",
            **garment,
        },
    }


def mean_pressure(case):
    state = initial_state(case)
    body, _ = body_from_config(CYLINDER)
    result = relax(state, body, Settings(tolerance=1e-10, progress=False))
    assert result.converged
    ev = result.final
    reaction = contact_reaction(ev.forces, ev.unbalanced, ev.on_body)
    return float(np.mean(np.linalg.norm(reaction, axis=1) / node_area(ev.x, state.grid)))


@pytest.mark.parametrize(("reduction", "set_strain"), [(0.2, 0.05), (0.25, 0.1)])
def test_a_worn_tube_is_a_new_tube_cut_larger_by_its_set(reduction, set_strain):
    worn = mean_pressure(tube(reduction, worn=True, set_strain={"weft": set_strain, "warp": 0}))
    new = mean_pressure(tube(1 - (1 - reduction) * (1 + set_strain)))
    assert abs(worn / new - 1) < 1e-3
    assert worn < 0.9 * mean_pressure(tube(reduction))  # the set costs compression


def test_a_set_along_the_tube_packs_more_courses_into_its_height():
    """The warp's set lengthens the tube, held between the same heights: (1 + s) more fabric
    per height, each course at the same hoop stress, so (1 + s) more pressure."""
    plain = mean_pressure(tube(0.2, worn=True, set_strain={"weft": 0.05, "warp": 0.0}))
    longer = mean_pressure(tube(0.2, worn=True, set_strain={"weft": 0.05, "warp": 0.03}))
    assert abs(longer / plain / 1.03 - 1) < 1e-3


def test_the_set_is_measured_in_the_cycles_of_the_lab_table():
    fabric = ingest(["data/materials/powernet.csv"]).fabric
    assert 0.0 < fabric.set_strain["weft"] < 0.05 and 0.0 < fabric.set_strain["warp"] < 0.05
    state = initial_state(tube(0.2, worn=True))
    new = initial_state(tube(0.2))
    ratio = state.grid.rest_length / new.grid.rest_length
    weft = state.grid.family_slices[0]
    np.testing.assert_allclose(ratio[weft], 1 + fabric.set_strain["weft"], rtol=1e-12)


def test_worn_without_a_known_set_is_refused(tmp_path):
    table = tmp_path / "clean.csv"
    table.write_text(
        "# thickness_mm: 0.5\ndirection,strain,stress_kPa\n"
        "weft,0,0\nweft,0.5,100\nwarp,0,0\nwarp,0.5,150\n"
    )
    with pytest.raises(InputError) as error:
        initial_state(tube(0.2, material=str(table), worn=True))
    assert error.value.field == "garment.set_strain.weft"
    with pytest.raises(InputError) as error:
        initial_state(tube(0.2, worn=True, set_strain={"weft": float("nan")}))
    assert error.value.field == "garment.set_strain.weft"
