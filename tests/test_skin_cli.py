"""The skin models through the command line: result variables, figures, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.cli import main

CYLINDER = {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}
GARMENT = {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [24, 4]}


def write(path, **case):
    path.write_text(
        yaml.safe_dump({"material": "powernet", "body": CYLINDER, "garment": GARMENT, **case})
    )
    return path


def test_a_case_on_tissue_with_friction_reports_indentation_and_friction(tmp_path):
    tissue = {**CYLINDER, "tissue": {"thickness": 0.02, "modulus": 2e4}}
    case = write(tmp_path / "soft.yaml", body=tissue, contact={"friction": 0.4})
    out = tmp_path / "soft"
    assert main(["--log-level", "WARNING", "run", str(case), "-o", str(out)]) == 0
    with xr.open_dataset(out / "result.nc") as ds:
        held = ds["contact"].values == 1
        assert held.all()
        # the layer's law, node by node: indentation = pressure h / E
        np.testing.assert_allclose(
            ds["indentation"].values, ds["pressure"].values * 0.02 / 2e4, rtol=1e-6
        )
        np.testing.assert_allclose(ds["skin_distance"].values, -ds["indentation"].values)
        assert ds["indentation"].attrs["units"] == "m"
        assert ds["friction_state"].attrs["flag_meanings"] == "off_skin stick slip"
        assert ds["friction_force"].attrs["units"] == "N"
        components = np.stack([ds[f"friction_force_{a}"].values for a in "xyz"], axis=-1)
        np.testing.assert_allclose(
            ds["friction_force"].values, np.linalg.norm(components, axis=-1), atol=1e-12
        )
        # the layer as the case gives it, node by node
        np.testing.assert_allclose(ds["tissue_thickness"].values, 0.02)
        np.testing.assert_allclose(ds["tissue_modulus"].values, 2e4)
        assert set(np.unique(ds["friction_state"].values)) <= {0, 1, 2}
        assert ds.attrs["solver_lags"] >= 1
    assert (out / "figures" / "indentation.png").is_file()
    assert (out / "figures" / "friction.png").is_file()


@pytest.mark.parametrize(
    ("case", "expected"),
    [
        (
            {"body": {**CYLINDER, "tissue": {"thickness": 0.02, "modulus": -1.0}}},
            "body.tissue.modulus",
        ),
        (
            {"body": {**CYLINDER, "tissue": {"thickness": float("nan"), "modulus": 2e4}}},
            "body.tissue.thickness",
        ),
        (
            {
                "body": {
                    **CYLINDER,
                    "tissue": {
                        "thickness": 0.02,
                        "modulus": 2e4,
                        "bands": [{"bottom": 0.0, "top": 0.2, "thickness": 0.01, "modulus": 1e4}],
                    },
                }
            },
            "body.tissue.bands[0]",
        ),
        ({"contact": {"friction": -0.2}}, "contact.friction"),
        ({"contact": {"friction": 0.3}, "solver": {"method": "explicit"}}, "solver.method"),
        (
            {"garment": {**GARMENT, "worn": True, "set_strain": {"weft": 1.5}}},
            "garment.set_strain.weft",
        ),
    ],
)
def test_bad_skin_input_is_one_line_and_exit_2_before_any_file(tmp_path, capsys, case, expected):
    path = write(tmp_path / "bad.yaml", **case)
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expected in err[0] and "bad.yaml" in err[0], err
    assert not out.exists() or not any(out.iterdir())
