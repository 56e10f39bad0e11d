"""Atomic file writing, netCDF read/write with CF conventions, and provenance.

Every file the project writes goes through `atomic_output`: it is written to a temporary file in
the destination folder and renamed over the destination only when complete, so a killed job
never leaves a half-written output (`os.replace` is atomic on POSIX file systems).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import hashlib
import json
import os
import shlex
import shutil
import sys
import tempfile
from collections.abc import Container, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cloth import __version__
from cloth.errors import InputError

if TYPE_CHECKING:
    import xarray as xr

CONVENTIONS = "CF-1.11"


def sha256(path: str | Path) -> str:
    """Hex sha256 of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it to ``path`` if the block succeeds.

    Examples
    --------
    >>> with atomic_output("out.txt") as tmp:  # doctest: +SKIP
    ...     tmp.write_text("done")
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp's 0600 would hide outputs from the group
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


@contextlib.contextmanager
def atomic_folder(path: str | Path) -> Iterator[Path]:
    """Yield a temporary folder beside ``path``; if the block succeeds, each file and folder
    written in it is renamed into ``path`` (created where missing), replacing only what has
    its name (anything else in ``path`` stays), else it is removed: the outputs of several
    stages appear together or not at all."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent))
    try:
        yield tmp
        path.mkdir(exist_ok=True)
        for entry in sorted(tmp.iterdir()):
            target = path / entry.name
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target)
            if entry.is_dir():
                os.chmod(entry, 0o777 & ~_umask())
            os.replace(entry, target)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp)


_COMMAND: list[str] | None = None


def set_command(argv: list[str]) -> None:
    """Record the command line that `history_line` reports (the CLI sets it)."""
    global _COMMAND
    _COMMAND = list(argv)


def history_line(argv: list[str] | None = None) -> str:
    """A CF ``history`` entry: UTC time and the command that made the file."""
    now = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    argv = argv if argv is not None else _COMMAND if _COMMAND is not None else sys.argv
    command = shlex.join([Path(argv[0]).name, *argv[1:]]) if argv else "cloth"
    return f"{now}: {command} (cloth {__version__})"


def global_attrs(title: str, previous: Mapping[str, object] | None = None) -> dict[str, str]:
    """CF global attributes; ``history`` appends to the previous file's history."""
    history = history_line()
    if previous and previous.get("history"):
        history = f"{previous['history']}\n{history}"
    return {
        "Conventions": CONVENTIONS,
        "title": title,
        "institution": "cloth",
        "source": f"cloth {__version__}",
        "cloth_version": __version__,
        "history": history,
    }


def to_attr(value: object) -> str | int | float:
    """A netCDF-safe attribute value: dicts/lists/None as JSON, bools as 0/1."""
    if isinstance(value, bool | np.bool_):
        return int(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, str | int | float) and not isinstance(value, bool):
        return value
    return json.dumps(value, default=str, sort_keys=True)


def write_netcdf(ds: xr.Dataset, path: str | Path, compress: tuple[str, ...] = ()) -> Path:
    """Write ``ds`` atomically with ``engine="netcdf4"``; coordinates get no _FillValue; the
    variables named in ``compress`` are zlib-compressed (lossless)."""
    encoding: dict[str, dict[str, object]] = {
        name: {"_FillValue": None} for name in ds.coords if ds[name].dtype.kind == "f"
    }
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "f":
            encoding[str(name)] = {"_FillValue": None}
    for name in compress:
        encoding.setdefault(name, {}).update(zlib=True, complevel=4, shuffle=True)
    with atomic_output(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
    return Path(path)


def read_netcdf(path: str | Path, kind: str, required: tuple[str, ...] = ()) -> xr.Dataset:
    """Open a project netCDF file fully into memory (the file is closed on return).

    Parameters
    ----------
    path : path
    kind : str
        What the file should be (its ``cloth_kind`` attribute), e.g. ``"material"``.
    required : tuple of str
        Variables that must be present.
    """
    import xarray as xr  # here, not at the top: a stage that writes no netCDF skips its import

    path = _existing(path)
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds.load()
    except Exception as exc:  # netCDF4/HDF5 raise a variety of errors for corrupt files
        raise _unreadable(path, exc) from None
    _check_contents(path, kind, ds.attrs.get("cloth_kind"), required, ds.variables)
    return ds


def read_fields(path: str | Path, kind: str, names: tuple[str, ...]) -> xr.Dataset:
    """Only the variables ``names`` of a project netCDF file of ``kind`` (`read_netcdf`'s
    checks and errors), read by netCDF4 directly: about a third of `read_netcdf`'s time on a
    192 x 96 result, where a figure reads every result of its sweep for its colour ranges."""
    import netCDF4
    import xarray as xr  # as in read_netcdf

    path = _existing(path)
    try:
        with netCDF4.Dataset(path) as handle:
            found = getattr(handle, "cloth_kind", None)
            fields = {
                name: (handle[name].dimensions, np.ma.filled(handle[name][:], np.nan))
                for name in names
                if name in handle.variables
            }
    except OSError as exc:
        raise _unreadable(path, exc) from None
    _check_contents(path, kind, found, names, fields)
    return xr.Dataset(fields, attrs={"cloth_kind": found})


def _existing(path: str | Path) -> Path:
    path = Path(path)
    if not path.is_file():
        raise InputError("file not found; check the path or run the stage that makes it", path)
    return path


def _unreadable(path: Path, exc: Exception) -> InputError:
    return InputError(f"not a readable netCDF file ({type(exc).__name__}); re-create it", path)


def _check_contents(
    path: Path, kind: str, found: str | None, required: tuple[str, ...], present: Container
) -> None:
    """`InputError` where the file's ``cloth_kind`` (``found``) is not ``kind``, or a variable
    of ``required`` is not in ``present``."""
    if found != kind:
        raise InputError(
            f"expected a cloth {kind} file, found {found or 'no cloth_kind attribute'}; "
            "pass the right file",
            path,
            "cloth_kind",
        )
    missing = [name for name in required if name not in present]
    if missing:
        raise InputError(
            f"missing variable {missing[0]!r}; the file is incomplete or from another cloth "
            "version, re-create it",
            path,
            missing[0],
        )


def resolve(path: str, base_dir: str | Path) -> Path:
    """A path from a case, relative to ``base_dir`` unless absolute."""
    candidate = Path(path).expanduser()
    return candidate if candidate.is_absolute() else Path(base_dir) / candidate


def variable(dims, values, units: str | None, long_name: str, **attrs: Any) -> xr.Variable:
    """A CF variable: ``values`` along ``dims`` with its ``units`` (None for one without, such
    as labels) and ``long_name``, plus ``attrs``. The project's one way to make one."""
    import xarray as xr  # as in read_netcdf

    base = {"long_name": long_name} if units is None else {"units": units, "long_name": long_name}
    return xr.Variable(dims, values, {**base, **attrs})


def node_variable(
    shape: tuple[int, int], values, units: str, long_name: str, **attrs: Any
) -> xr.Variable:
    """A per-node CF variable on dims (``row``, ``col``): ``values`` ((rows * cols,) or
    (rows, cols)) reshaped to ``shape`` = (rows, cols), i.e. (grid.m, grid.n)."""
    return variable(("row", "col"), np.asarray(values).reshape(shape), units, long_name, **attrs)


def flag_variable(shape: tuple[int, int], values, long_name: str, meanings: str) -> xr.Variable:
    """A per-node CF flag variable (`node_variable`): ``values`` 0, 1, ... meaning the words of
    ``meanings``."""
    count = len(meanings.split())
    return node_variable(
        shape,
        values,
        "1",
        long_name,
        flag_values=np.arange(count, dtype=np.int8),
        flag_meanings=meanings,
    )
