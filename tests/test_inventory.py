"""Every number a user reads has a test (docs/testing.md, "What users read").

The inventory's own checks (every row names tests that exist, a column added without a row is
caught), and the tests that read one relaxed case's files back by a second route: summary.csv
column by column against result.nc in the unit its header names, and result.nc's node, spring and
total fields recomputed from its positions, rest lengths and lab curves with numpy.
"""

from __future__ import annotations

import csv
import math
import re

import numpy as np
import pytest
import xarray as xr
import yaml
from scipy.integrate import quad

from cloth.results.richardson import RANGE_NOTE
from tests import inventory
from tests.conftest import MMHG_BY_DEFINITION as MMHG
from tests.conftest import run_result

CONE = {"cone": {"radius_bottom": 0.13, "radius_top": 0.09, "bottom": 0.0, "top": 0.5}}
#: summary.csv's columns as result.nc's per-line variables, in the unit the header's suffix names
#: (the factor from the variable's SI unit).
SUMMARY = {
    "height_m": ("landmark_height", 1.0),
    "pressure_mean_Pa": ("pressure_mean", 1.0),
    "pressure_max_Pa": ("pressure_max", 1.0),
    "pressure_min_Pa": ("pressure_min", 1.0),
    "pressure_mean_kPa": ("pressure_mean", 1e-3),
    "pressure_mean_mmHg": ("pressure_mean", 1 / MMHG),
    "pressure_max_mmHg": ("pressure_max", 1 / MMHG),
    "pressure_min_mmHg": ("pressure_min", 1 / MMHG),
    "tension_weft_mean_N_per_m": ("tension_mean", 1.0),
    "row_pressure_mean_Pa": ("row_pressure_mean", 1.0),
    "pressure_mean_error_Pa": ("pressure_mean_error", 1.0),
    "pressure_mean_error_mmHg": ("pressure_mean_error", 1 / MMHG),
    "pressure_mean_order": ("pressure_mean_order", 1.0),
    "pressure_mean_extrapolated_Pa": ("pressure_mean_extrapolated", 1.0),
    "pressure_max_error_Pa": ("pressure_max_error", 1.0),
    "pressure_min_error_Pa": ("pressure_min_error", 1.0),
    "tension_weft_mean_error_N_per_m": ("tension_mean_error", 1.0),
    "row_spacing_mm": ("row_spacing", 1e3),
    "warp_slack": ("landmark_slack_warp", 1.0),
    "off_body": ("landmark_off_body", 1.0),
}
#: summary.csv's error note per estimate flag (result.nc's ``flag_meanings``) the cone has.
NOTES = {"observed": "", "data_range": RANGE_NOTE}
#: summary.csv's columns of the whole case: result.nc's scalars.
SCALARS = ("max_strain_weft", "lab_max_strain_weft", "max_strain_warp", "lab_max_strain_warp")


@pytest.fixture(scope="module")
def cone(tmp_path_factory):
    """A tube on a cone (its warp stretched: one stable equilibrium, every row its own
    pressure) at 32 x 12 with its error estimate: the output folder."""
    case = {
        "material": "powernet",
        "body": CONE,
        "landmarks": {"low": 0.17, "mid": 0.25},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": 0.15,
            "lengthwise_reduction": 0.1,
            "grid": [32, 12],
            "error_estimate": True,
        },
    }
    return run_result(tmp_path_factory.mktemp("inventory"), case)


def test_every_test_the_inventory_names_exists_and_every_row_names_one():
    known = inventory.test_functions()
    table = inventory.rows()
    assert len(table) > 200  # the section was found and parsed
    for row in table:
        assert row.tests, f"{row.file}: {row.name} names no test"
        for name in row.tests:
            assert name in known, f"{row.file}: {row.name} names {name}, which is not a test"
    keys = [(row.file, row.name) for row in table]
    assert len(keys) == len(set(keys)), "a row is listed twice"


def test_a_column_or_variable_with_no_row_or_another_unit_is_named(cone, tmp_path):
    summary = cone / "summary.csv"
    assert inventory.unlisted([summary, cone / "result.nc"]) == []
    with open(summary, newline="") as handle:
        table = list(csv.reader(handle))
    extra = tmp_path / "summary.csv"
    with open(extra, "w", newline="") as handle:
        csv.writer(handle).writerows([[*table[0], "pressure_mode_Pa"], *table[1:]])
    assert inventory.unlisted([extra]) == ["summary.csv: pressure_mode_Pa has no row"]
    with xr.open_dataset(cone / "result.nc") as ds:
        ds = ds.load()
    ds["pressure"].attrs["units"] = "kPa"
    ds["pressure_peak"] = ds["pressure"]
    ds.to_netcdf(tmp_path / "result.nc")
    assert sorted(inventory.unlisted([tmp_path / "result.nc"])) == [
        "result.nc: pressure is in 'kPa', the inventory says 'Pa'",
        "result.nc: pressure_peak has no row",
    ]


def test_every_summary_column_is_result_nc_s_value_in_its_header_s_unit(cone):
    with xr.open_dataset(cone / "result.nc") as ds:
        ds = ds.load()
    with open(cone / "summary.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    assert [r["landmark"] for r in table] == ds["landmark"].values.tolist()
    checked = {"case", "landmark", "converged", "error_note", "friction_note"}
    for k, row in enumerate(table):
        assert row["case"] == cone.name
        assert int(row["converged"]) == int(ds.attrs["converged"]) == 1
        for column, (name, factor) in SUMMARY.items():
            value = float(ds[name].values[k]) * factor
            written = float(row[column])
            assert math.isnan(written) == math.isnan(value), column
            if not math.isnan(value):
                assert written == pytest.approx(value, rel=1e-5, abs=1e-12), column
        for name in SCALARS:
            assert float(row[name]) == pytest.approx(float(ds[name]), rel=1e-5), name
        error, mean = float(ds["pressure_mean_error"][k]), float(ds["pressure_mean"][k])
        percent = float(row["pressure_mean_error_percent"])
        assert (math.isnan(percent) and math.isnan(error)) or percent == pytest.approx(
            100 * error / mean, rel=1e-5
        )
        # a line without an estimate says why (its flag's meaning); one with an estimate nothing
        code = int(ds["pressure_mean_estimate"][k])
        meaning = ds["pressure_mean_estimate"].attrs["flag_meanings"].split()[code]
        assert row["error_note"] == NOTES[meaning]
        assert row["friction_note"] == ""  # the case has no friction
    checked |= set(SUMMARY) | set(SCALARS) | {"pressure_mean_error_percent"}
    assert set(table[0]) == checked
    # one line has an order and one is stated from its levels' range (its order outside
    # 0.5-4), so both notes above were checked
    assert sorted(ds["pressure_mean_estimate"].values.tolist()) == [0, 7]


def _stress(ds: xr.Dataset, family: str, strain: np.ndarray) -> np.ndarray:
    """The lab curve of ``family`` stored in result.nc at ``strain`` (Pa): linear between its
    knots, the compression modulus below zero strain."""
    knots, stresses = ds[f"{family}_knot_strain"].values, ds[f"{family}_knot_stress"].values
    modulus = float(ds[f"{family}_compression_modulus"])
    return np.where(strain < 0, modulus * strain, np.interp(strain, knots, stresses))


def _node_mean(values: np.ndarray, a: np.ndarray, b: np.ndarray, nodes: int) -> np.ndarray:
    """Each node's mean of ``values`` over the springs that end at it."""
    total, count = np.zeros(nodes), np.zeros(nodes)
    np.add.at(total, a, values)
    np.add.at(total, b, values)
    np.add.at(count, a, 1)
    np.add.at(count, b, 1)
    return total / count


def test_result_nc_s_fields_are_their_definitions_from_positions_and_curves(cone):
    with xr.open_dataset(cone / "result.nc") as ds:
        ds = ds.load()
    with xr.open_dataset(cone / "initial.nc") as initial:
        initial = initial.load()
    m, n = ds.sizes["row"], ds.sizes["col"]
    assert ds["row"].values.tolist() == list(range(m))
    assert ds["col"].values.tolist() == list(range(n))
    xyz = np.stack([ds[c].values.ravel() for c in "xyz"], axis=1)
    a, b = ds["spring_node_a"].values, ds["spring_node_b"].values
    rest = ds["rest_length"].values
    family = ds["spring_family"].values
    assert ds["spring_family"].attrs["flag_meanings"].split()[:2] == ["weft", "warp"]
    weft, warp = family == 0, family == 1
    # weft springs join neighbours around a row, warp springs neighbours up a column
    assert np.all(a[weft] // n == b[weft] // n) and np.all(
        np.isin((b[weft] - a[weft]) % n, (1, n - 1))
    )
    assert np.all(b[warp] - a[warp] == n)
    strain = np.linalg.norm(xyz[b] - xyz[a], axis=1) / rest - 1
    np.testing.assert_allclose(ds["spring_strain"].values, strain, atol=1e-12)
    np.testing.assert_array_equal(ds["spring_slack"].values, (strain <= 1e-9).astype(np.int8))
    # the threshold the file states is the one the flags were computed with
    from cloth.files.result import SLACK_STRAIN

    assert "strain <= 1e-9" in ds["spring_slack"].attrs["long_name"] and SLACK_STRAIN == 1e-9
    thickness = float(ds["thickness"])
    for name, springs in (("weft", weft), ("warp", warp)):
        stress = _stress(ds, name, strain[springs])
        np.testing.assert_allclose(ds["spring_stress"].values[springs], stress, rtol=1e-9)
        assert float(ds[f"max_strain_{name}"]) == pytest.approx(strain[springs].max(), rel=1e-9)
        lab = float(ds[f"{name}_knot_strain"][-1])
        assert float(ds[f"lab_max_strain_{name}"]) == lab
        node_stress = _node_mean(stress, a[springs], b[springs], m * n).reshape(m, n)
        node_strain = _node_mean(strain[springs], a[springs], b[springs], m * n).reshape(m, n)
        np.testing.assert_allclose(ds[f"stress_{name}"].values, node_stress, rtol=1e-9)
        np.testing.assert_allclose(ds[f"strain_{name}"].values, node_strain, atol=1e-12)
        np.testing.assert_allclose(ds[f"tension_{name}"].values, node_stress * thickness)
    beyond = np.zeros(m * n, bool)
    for name, springs in (("weft", weft), ("warp", warp)):
        over = strain[springs] > float(ds[f"lab_max_strain_{name}"])
        beyond[a[springs][over]] = beyond[b[springs][over]] = True
    np.testing.assert_array_equal(ds["beyond_lab_range"].values.ravel().astype(bool), beyond)
    # a weft spring's area is the thickness times its rest row spacing (half at the edges)
    v = ds["v"].values[:, 0]
    spacing = np.diff(v)
    width = np.concatenate([[spacing[0] / 2], (spacing[:-1] + spacing[1:]) / 2, [spacing[-1] / 2]])
    np.testing.assert_allclose(ds["area"].values[weft], thickness * width[a[weft] // n])
    # rest coordinates: u the weft rest lengths summed along the row, v along the column
    u = np.concatenate([[0.0], np.cumsum(rest[weft][: n - 1])])
    np.testing.assert_allclose(ds["u"].values[0], u, atol=1e-15)
    np.testing.assert_allclose(ds["pattern_height"].values, v)
    row_rest = np.zeros(m)
    np.add.at(row_rest, a[weft] // n, rest[weft])
    np.testing.assert_allclose(ds["rest_circumference"].values, row_rest, rtol=1e-12)
    # on the cone the row's reduction is from the girth 2 pi r at the height it was cut for
    radius = 0.13 + (0.09 - 0.13) * ds["cut_height"].values / 0.5
    np.testing.assert_allclose(ds["row_reduction"].values, 1 - row_rest / (2 * np.pi * radius))
    np.testing.assert_allclose(ds["row_reduction"].values, 0.15, atol=1e-12)
    # the node areas tile the deformed tube: two triangles per quad
    grid = xyz.reshape(m, n, 3)
    right = np.roll(grid, -1, axis=1)
    lower = np.cross(right[:-1] - grid[:-1], grid[1:] - grid[:-1])
    upper = np.cross(right[1:] - grid[1:], right[1:] - right[:-1])
    tube = 0.5 * (np.linalg.norm(lower, axis=2).sum() + np.linalg.norm(upper, axis=2).sum())
    assert ds["node_area"].values.sum() == pytest.approx(tube, rel=1e-12)
    pressure = ds["pressure"].values
    np.testing.assert_allclose(ds["pressure_mmHg"].values * MMHG, pressure, rtol=1e-12)
    np.testing.assert_allclose(
        ds["p_laplace_difference"].values, ds["p_laplace"].values - pressure, atol=1e-9
    )
    integral = float((pressure * ds["node_area"].values).sum())
    assert float(ds["pressure_integral"]) == pytest.approx(integral, rel=1e-12)
    # every node is on the cone, pressed along its normal: the reactions sum to the integral,
    # and the fabric's force on the body is along the axis (the cone's taper), its moment 0
    assert int(ds["contact"].sum()) == m * n
    assert float(ds["normal_force"]) == pytest.approx(integral, rel=1e-6)
    force = ds["total_force"].values
    assert np.hypot(force[0], force[1]) < 1e-9 * integral
    assert np.linalg.norm(ds["total_moment"].values) < 1e-9 * integral
    # the energy is the curves integrated to each spring's strain, times its rest volume
    energy = 0.0
    for name, springs in (("weft", weft), ("warp", warp)):
        knots = ds[f"{name}_knot_strain"].values
        stresses = ds[f"{name}_knot_stress"].values
        modulus = float(ds[f"{name}_compression_modulus"])
        density = [
            quad(np.interp, 0, e, args=(knots, stresses), limit=200)[0]
            if e > 0
            else 0.5 * modulus * e * e
            for e in strain[springs]
        ]
        energy += float(np.dot(density, ds["area"].values[springs] * rest[springs]))
    assert float(ds["energy"][-1]) == pytest.approx(energy, rel=1e-8)
    # the initial fields are initial.nc's, the initial stress the curve at their strains
    for c in "xyz":
        np.testing.assert_array_equal(ds[f"{c}_initial"].values, initial[c].values)
    start = np.stack([initial[c].values.ravel() for c in "xyz"], axis=1)
    strain0 = np.linalg.norm(start[b[weft]] - start[a[weft]], axis=1) / rest[weft] - 1
    stress0 = _node_mean(_stress(ds, "weft", strain0), a[weft], b[weft], m * n).reshape(m, n)
    np.testing.assert_allclose(ds["stress_weft_initial"].values, stress0, rtol=1e-9)
    # the lab table's header (data/materials/powernet.csv): 0.55 mm, 190 g/m2
    assert float(ds["thickness"]) == pytest.approx(0.55e-3, rel=1e-12)
    assert float(ds["areal_density"]) == pytest.approx(0.190, rel=1e-12)
    assert ds["landmark_height"].values.tolist() == [0.17, 0.25]
    # the solver's history: Newton's last step to the tolerance; the nodes on the body and
    # their depth in the cone (its surface at the height of each node, along its normal)
    meanings = ds["iteration_method"].attrs["flag_meanings"].split()
    assert meanings[int(ds["iteration_method"][-1])] == "newton"
    assert float(ds["residual"][-1]) <= float(ds.attrs["solver_tolerance"])
    assert int(ds["contacts"][-1]) == int(ds["contact"].sum())
    taper = (0.13 - 0.09) / 0.5
    depth = (0.13 - taper * xyz[:, 2] - np.hypot(xyz[:, 0], xyz[:, 1])) / np.hypot(1, taper)
    assert float(ds["penetration"][-1]) == pytest.approx(max(depth.max(), 0.0), abs=1e-12)
    moved = np.linalg.norm(xyz - start, axis=1).max()
    assert float(ds["step"][0]) == 0 and moved <= float(ds["step"].sum()) * (1 + 1e-12)
    assert abs(float(ds["turning_force"][-1])) < 1e-9 * integral  # in equilibrium
    # the edges slide (the default): the top and bottom rows, where only the support pushes
    constraint = ds["constraint"].values
    assert ds["constraint"].attrs["flag_meanings"].split() == ["free", "sliding", "fixed"]
    assert np.all(constraint[[0, -1]] == 1) and np.all(constraint[1:-1] == 0)
    support = ds["edge_support_force"].values
    assert np.all(support[1:-1] == 0) and np.all(support[[0, -1]] != 0)
    # the fabric's vertical force on the body is what the supports hold (Newton's third law)
    assert force[2] == pytest.approx(support.sum(), rel=1e-6)
    # the finest level is the result's own grid and girth-line values
    assert ds["level_n"].values.tolist() == [32, 16, 8]
    assert ds["level_m"].values.tolist() == [12, 6, 3]
    for name in ("pressure_mean", "pressure_max", "pressure_min", "tension_mean"):
        np.testing.assert_array_equal(ds[f"level_{name}"].values[0], ds[name].values)
    # the row spacing at a line: the deformed spacing of the rows about its height
    z = ds["z"].values.mean(axis=1)
    for k, height in enumerate(ds["landmark_height"].values):
        j = int(np.searchsorted(z, height)) - 1
        chord = np.linalg.norm(grid[j + 1] - grid[j], axis=1).mean()
        assert float(ds["row_spacing"][k]) == pytest.approx(chord, rel=0.02)


SCHEMAS = {
    "case.yaml": inventory.ROOT / "cloth" / "schemas" / "case.schema.yaml",
    "config.yaml": inventory.ROOT / "workflow" / "schemas" / "config.schema.yaml",
}


def _schema_keys(path, what: str) -> dict[str, object]:
    """Every ``what`` (``enum`` or ``default``) of a JSON schema by its key's dotted path."""
    out: dict[str, object] = {}

    def walk(node, keys):
        if not isinstance(node, dict):
            return
        if what in node and keys:
            out[".".join(keys)] = node[what]
        for key, value in node.items():
            if key in ("properties", "patternProperties"):
                for name, child in value.items():
                    walk(child, [*keys, name])
            elif key in ("items", "additionalProperties"):
                walk(value, keys)
            elif key in ("oneOf", "anyOf", "allOf"):
                for child in value:
                    walk(child, keys)

    walk(yaml.safe_load(path.read_text()), [])
    return out


def test_every_enumerated_option_has_a_row_whose_tests_select_it():
    table = inventory.listed()
    sources = {path.name: path.read_text() for path in (inventory.ROOT / "tests").glob("*.py")}
    for file, schema in SCHEMAS.items():
        for key, values in _schema_keys(schema, "enum").items():
            for value in values:
                row = table.get((file, f"{key}: {value}"))
                assert row is not None and row.unit == "option", f"{file}: {key}: {value}"
                for test in row.tests:
                    source = sources[test.split("::")[0]]
                    assert f'"{value}"' in source or f"'{value}'" in source, (key, value, test)


def _states(doc_lines: list[str], key: str, value: object) -> bool:
    """Whether a line of docs/config.md naming ``key`` (its last part) states ``value``."""
    name = key.rsplit(".", 1)[-1]
    for line in doc_lines:
        if not re.search(rf"(^|[\s`(]){re.escape(name)}(`|:|\s\()", line):
            continue
        if isinstance(value, bool):
            if str(value).lower() in line.lower():
                return True
        elif isinstance(value, int | float):
            numbers = re.findall(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?", line)
            if any(float(n) == float(value) for n in numbers):
                return True
        elif re.search(rf"(?<![\w-]){re.escape(str(value))}(?![\w-])", line):
            return True
    return False


#: The case keys of a garment's pieces (`cloth.case.pieces`), read from a case that has them.
PIECE_KEYS = ("garment.bands.", "garment.layers.", "garment.panels.", "garment.seams.")


def _effective(case, key: str):
    """The value a validated case carries for the case key ``key``."""
    if key.startswith("girth_reading."):
        return getattr(case.reading, key.split(".")[1])
    node = case.to_dict()
    for part in key.split("."):
        node = node[0] if isinstance(node, list) else node  # a list's first item (a band)
        node = node[part]
    return node


def test_every_default_is_the_schema_s_the_case_s_and_the_one_docs_config_states(tmp_path):
    from cloth.case.case import validate_case
    from tests.conftest import capped_cylinder, write_obj

    rows = {(r.file, r.name): r for r in inventory.rows() if r.unit.startswith("default:")}
    stated = {key: yaml.safe_load(row.unit.split(":", 1)[1]) for key, row in rows.items()}
    for file, schema in SCHEMAS.items():
        for key, value in _schema_keys(schema, "default").items():
            if value in ({}, []):
                continue  # a block or list that is absent by default, not a setting
            assert (file, key) in stated, f"{file}: {key} has a default ({value!r}) and no row"
            assert stated[file, key] == value, f"{file}: {key}"
    doc = (inventory.ROOT / "docs" / "config.md").read_text().splitlines()
    for (_, key), value in stated.items():
        assert _states(doc, key, value), f"docs/config.md does not state {key}'s default {value}"
    write_obj(tmp_path / "body.obj", *capped_cylinder(0.1, 0.5, 24))
    garment = {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [16, 8]}
    bodies = {
        "mesh": {"mesh": str(tmp_path / "body.obj")},
        "torso": {"torso": {"size": "M"}},
        "leg": {"leg": {"size": "M"}},
        "cylinder": {"cylinder": {"radius": 0.1}},
        "elliptic_cylinder": {"elliptic_cylinder": {"a": 0.1, "b": 0.08}},
        "cone": {"cone": {"radius_bottom": 0.1, "radius_top": 0.08}},
    }
    cases = {
        kind: validate_case({"material": "powernet", "body": body, "garment": garment})
        for kind, body in bodies.items()
    }
    base = {"material": "powernet", "body": bodies["cylinder"]}
    # a garment of several pieces, each item's defaulted keys left out (cloth.case.pieces)
    several = {
        **garment,
        "bands": [{"name": "band", "material": "elastic25", "width": 0.02, "reduction": 0.1}],
        "layers": [
            {"material": "controlnet", "from_deg": 0, "to_deg": 90, "bottom": 0.2, "top": 0.3}
        ],
        "panels": [{"material": "powernet", "from_deg": 0, "to_deg": 360}],
        "seams": {},
    }
    pieces = validate_case({"material": "powernet", "body": bodies["cylinder"], "garment": several})
    typed = pieces.garment.pieces  # the types apply the same defaults
    assert typed.bands[0].at == stated["case.yaml", "garment.bands.at"]
    assert typed.bands[0].layers == stated["case.yaml", "garment.bands.layers"]
    assert typed.layers[0].layers == stated["case.yaml", "garment.layers.layers"]
    assert typed.seams.allowance_mm == stated["case.yaml", "garment.seams.allowance_mm"]
    from cloth.case.reading import Reading

    for (file, key), value in stated.items():
        if key.startswith("girth_reading."):  # the library's own default too
            assert getattr(Reading(), key.split(".")[1]) == value, key
        if file != "case.yaml" or key == "contact.friction":
            continue  # the config's keys are the schema's (above); friction: no contact block
        parts = key.split(".")
        kind = parts[1] if key.startswith("body.") and len(parts) == 3 else "mesh"
        case = cases[kind] if key.startswith("body.") else cases["cylinder"]
        if key.startswith(PIECE_KEYS):
            case = pieces
        if key in ("garment.accuracy", "garment.max_nodes"):  # filled for grid: auto alone
            assert key.split(".")[1] not in case.to_dict()["garment"], key
            case = validate_case({**base, "garment": {**garment, "grid": "auto"}})
        assert _effective(case, key) == value, key
    # a contact block without friction is frictionless
    frictionless = validate_case(
        {"material": "powernet", "body": bodies["cylinder"], "garment": garment, "contact": {}}
    )
    assert (
        frictionless.to_dict().get("contact", {}).get("friction", 0.0)
        == stated["case.yaml", "contact.friction"]
    )


def test_every_path_key_of_a_case_has_a_row():
    from cloth.case.locations import PATH_KEYS

    table = inventory.listed()
    for keys in PATH_KEYS:
        row = table.get(("case.yaml", ".".join(keys)))
        assert row is not None and row.unit == "path", keys


def test_the_provenance_names_the_code_s_revision_from_any_working_folder(tmp_path, monkeypatch):
    """result.nc's ``git_revision`` is the revision of the code that wrote it, not of the
    repository the user runs it in (here another repository with its own commit)."""
    import shutil
    import subprocess

    from cloth.files.result import git_revision

    git = shutil.which("git")
    if git is None:
        pytest.skip("git is not installed")
    package = inventory.ROOT / "cloth"
    here = subprocess.run(
        [git, "rev-parse", "--short", "HEAD"], cwd=package, capture_output=True, text=True
    ).stdout.strip()
    here = here or "unknown"  # the code outside a checkout (an installed copy) says so
    other = tmp_path / "other"
    other.mkdir()
    for command in (
        ["init", "-q"],
        ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "--allow-empty", "-m", "x"],
    ):
        subprocess.run([git, *command], cwd=other, check=True)
    monkeypatch.chdir(other)
    assert git_revision() == here


#: The typed blocks of a case (`cloth.case`) and the case key each is read from.
TYPED_BLOCKS = {"solver": "solver", "garment": "garment", "contact": "contact"}


def test_every_default_is_the_one_the_code_applies_and_its_types_own():
    """A case built with each defaulted key left out carries the schema's default in the typed
    object the code reads (`Case.solver`, `Case.garment`, `Case.contact`, `Case.fabric_scale`),
    and the type's own default (a library user's `Settings()`) is the same."""
    import dataclasses

    from cloth.case.case import validate_case

    garment = {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [16, 8]}
    base = {"material": "powernet", "body": {"cylinder": {"radius": 0.1}}, "garment": garment}
    case = validate_case(base)
    checked = 0
    for key, value in _schema_keys(SCHEMAS["case.yaml"], "default").items():
        block, _, name = key.partition(".")
        if key == "fabric_scale":
            assert case.fabric_scale == value
            checked += 1
        if block not in TYPED_BLOCKS or "." in name:
            continue
        typed = getattr(case, TYPED_BLOCKS[block])
        assert getattr(typed, name) == value, f"{key}: the code applies {getattr(typed, name)!r}"
        field = {f.name: f for f in dataclasses.fields(typed)}[name]
        if field.default is not dataclasses.MISSING:
            assert field.default == value, f"{key}: {type(typed).__name__}'s own default"
        checked += 1
    assert checked >= 18  # every solver, garment and contact default above, and fabric_scale


#: A default a description states as one value: "Default X" or "(default X)", X a number, a
#: boolean or a list, ended by punctuation or the text's end ("default 1e-3 x the shortest
#: spring" or "default true where ..." is no single value and is left to the text).
STATED_DEFAULT = re.compile(
    r"\b[Dd]efault:?\s+(\[[^\]]*\]|-?\d+(?:\.\d+)?(?:e-?\d+)?|true|false)(?=\s*(?:[.;,)(]|$))"
)


def _described_defaults(path) -> dict[str, object]:
    """Every key of a JSON schema whose description states a default (`STATED_DEFAULT`), by
    its dotted path, the value read as YAML."""
    out: dict[str, object] = {}
    for key, text in _schema_keys(path, "description").items():
        found = STATED_DEFAULT.search(" ".join(str(text).split()))
        if found:
            out[key] = yaml.safe_load(found.group(1))
    return out


def test_every_default_a_description_states_is_one_value_the_code_applies():
    """A default stated in a key's description (what docs/reference/keys.md shows) is the
    schema's ``default`` (so the rule above, the docs and the code's types all see it), and
    a size chart entry's is ``cloth sizes``'s own (the job passes only what an entry gives)."""
    from cloth.cli.parser import build_parser
    from cloth.files.population import AGES
    from cloth.pipeline.sizecharts import OPTIONS

    case_keys = _described_defaults(SCHEMAS["case.yaml"])
    defaults = _schema_keys(SCHEMAS["case.yaml"], "default")
    assert "garment.accuracy" in case_keys  # the one that once stated it in its text alone
    for key, value in case_keys.items():
        assert key in defaults, f"case.yaml: {key} states default {value!r} in its text only"
        assert defaults[key] == value, f"case.yaml: {key}: text {value!r}, schema {defaults[key]!r}"
    config_keys = _described_defaults(SCHEMAS["config.yaml"])
    config_defaults = _schema_keys(SCHEMAS["config.yaml"], "default")
    for key, value in config_keys.items():
        if key in config_defaults:
            assert config_defaults[key] == value, key
    args = build_parser().parse_args(["sizes", "case.yaml", "--target", "B=23:32", "-o", "x"])
    checked = 0
    for key, value in config_keys.items():
        entry, _, name = key.partition(".")
        if entry != "size_charts":
            continue
        if name == "ages":
            applied = list(AGES) if args.ages is None else args.ages
        else:
            applied = getattr(args, OPTIONS[name].lstrip("-").replace("-", "_"))
        assert applied == value, (
            f"config.yaml: {key} states {value!r}, cloth sizes applies {applied!r}"
        )
        checked += 1
    assert checked >= 5  # coverage, max_sizes, max_variants, rounds, ages
