"""Files: atomic writes leave nothing half-written and give outputs the usual permissions."""

from __future__ import annotations

import os
import stat

import pytest

from cloth.io import atomic_output, sha256


def test_an_atomic_output_follows_the_umask_and_a_failure_leaves_nothing(tmp_path):
    old = os.umask(0o022)
    try:
        with atomic_output(tmp_path / "out.txt") as tmp:
            tmp.write_text("done")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "out.txt").stat().st_mode) == 0o644  # not mkstemp's 0600
    with pytest.raises(RuntimeError), atomic_output(tmp_path / "half.txt") as tmp:
        tmp.write_text("half")
        raise RuntimeError
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]
    # sha256 of b"done"
    assert sha256(tmp_path / "out.txt") == (
        "a4c3ed04a95a3da14a9d235c83d868bed7c0f45cf7f3faa751ee8f50598d2211"
    )


def test_read_fields_reads_only_the_named_variables_as_written_and_refuses_as_read_netcdf(
    tmp_path,
):
    """The figures' peer reader (issue 54): the named variables with their dims and values as
    written (a NaN, a masked fill, float32 kept), nothing else; the wrong kind, a missing
    variable, a missing file and a text file each refused naming the file and the field."""
    import numpy as np
    import xarray as xr

    from cloth.errors import InputError
    from cloth.io import read_fields, write_netcdf

    values = np.arange(6.0).reshape(2, 3)
    values[1, 2] = np.nan
    ds = xr.Dataset(
        {
            "stress_weft": (("row", "col"), values, {"units": "Pa"}),
            "pressure_mmHg": (("row", "col"), np.float32(values / 3), {"units": "mmHg"}),
            "other": ("row", [1.0, 2.0]),
        },
        attrs={"cloth_kind": "result"},
    )
    path = write_netcdf(ds, tmp_path / "result.nc")
    read = read_fields(path, "result", ("stress_weft", "pressure_mmHg"))
    assert sorted(read.data_vars) == ["pressure_mmHg", "stress_weft"]
    assert read["stress_weft"].dims == ("row", "col")
    np.testing.assert_array_equal(read["stress_weft"].values, values)  # NaN where written
    assert read["pressure_mmHg"].dtype == np.float32
    np.testing.assert_array_equal(read["pressure_mmHg"].values, np.float32(values / 3))
    with pytest.raises(InputError) as kind:
        read_fields(path, "material", ("stress_weft",))
    assert kind.value.field == "cloth_kind" and "expected a cloth material file" in str(kind.value)
    with pytest.raises(InputError) as missing:
        read_fields(path, "result", ("stress_weft", "stress_warp"))
    assert missing.value.field == "stress_warp" and str(missing.value.source) == str(path)
    with pytest.raises(InputError, match="file not found"):
        read_fields(tmp_path / "none.nc", "result", ("stress_weft",))
    (tmp_path / "text.nc").write_text("not netCDF")
    with pytest.raises(InputError, match="not a readable netCDF file"):
        read_fields(tmp_path / "text.nc", "result", ("stress_weft",))


def test_an_atomic_folder_publishes_all_its_files_or_none_and_keeps_the_others(tmp_path):
    from cloth.io import atomic_folder

    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("the user's")
    (out / "sub").mkdir()
    (out / "sub" / "old.txt").write_text("stale")
    with pytest.raises(RuntimeError), atomic_folder(out) as folder:
        (folder / "a.csv").write_text("1")
        raise RuntimeError("the second stage fails")
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt", "sub"]
    assert not list(tmp_path.glob(".out.*"))
    with atomic_folder(out) as folder:
        (folder / "a.csv").write_text("1")
        (folder / "sub").mkdir()
        (folder / "sub" / "new.txt").write_text("new")
    assert sorted(p.name for p in out.iterdir()) == ["a.csv", "mine.txt", "sub"]
    assert [p.name for p in (out / "sub").iterdir()] == ["new.txt"]  # her folder, replaced whole
    assert (out / "mine.txt").read_text() == "the user's"
