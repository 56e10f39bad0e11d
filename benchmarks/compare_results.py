"""Compare the data variables of two pipeline runs bit for bit: results/sweep.nc and every case's
result.nc. ``python benchmarks/compare_results.py BEFORE AFTER`` (two working directories of
``snakemake``); prints each file and the variables that differ, and exits 1 if any do.

Used to check that a renovation left the default pipeline's outputs unchanged (docs/
architecture.md)."""

import glob
import os
import sys

import numpy as np
import xarray as xr


def same(a: str, b: str) -> list[str]:
    """The data variables of netCDF files ``a`` and ``b`` that differ (or exist in one only)."""
    with xr.open_dataset(a) as x, xr.open_dataset(b) as y:
        names = set(x.data_vars) | set(y.data_vars)
        bad = []
        for n in sorted(names):
            if n not in x or n not in y:
                bad.append(f"{n}: only in one")
                continue
            va, vb = x[n].values, y[n].values
            if va.shape != vb.shape or va.dtype != vb.dtype:
                bad.append(f"{n}: shape/dtype")
                continue
            if va.dtype.kind in "fc":
                if not np.array_equal(va, vb, equal_nan=True):
                    bad.append(f"{n}: differs (max {np.nanmax(np.abs(va - vb))})")
            elif not np.array_equal(va, vb):
                bad.append(f"{n}: differs")
        return bad


if __name__ == "__main__":
    before, after = sys.argv[1], sys.argv[2]
    files = [
        "results/sweep.nc",
        *sorted(
            os.path.relpath(p, before) for p in glob.glob(f"{before}/results/cases/*/result.nc")
        ),
    ]
    total = 0
    for f in files:
        bad = same(f"{before}/{f}", f"{after}/{f}")
        total += len(bad)
        print(f, "bit-identical data variables" if not bad else bad)
    print("differences:", total)
    sys.exit(1 if total else 0)
