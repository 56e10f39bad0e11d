"""Paths as users give them, checked before any work: their form (length, characters), an
input's existence and readability (a file, not a folder), and whether an output can be written
where it is asked for (its folder is a folder, or can be made; it is not itself a folder).

Each check raises `InputError` naming the source, the field and the fix in one line; a path too
long to print is shortened in the message.
"""

from __future__ import annotations

import os
from pathlib import Path

from cloth.errors import InputError

#: Longest file name (one component) and whole path, in bytes, that POSIX systems take.
NAME_MAX = 255
PATH_MAX = 4096
#: Characters of a value shown in a message (a longer one is shortened: not a real path).
SHOWN = 240


def shown(value: object) -> str:
    """``value`` as a message shows it: its repr, shortened past `SHOWN` characters."""
    text = repr(str(value))
    if len(text) <= SHOWN:
        return text
    return f"{text[: SHOWN // 2]}...{text[-SHOWN // 4 :]} ({len(str(value))} characters)"


def path_form(value: object, source: str | Path | None, field: str | None) -> Path:
    """``value`` as a path if it has a path's form: non-empty text without NUL characters, at
    most `PATH_MAX` bytes, each name at most `NAME_MAX` bytes."""
    if isinstance(value, Path):
        value = str(value)
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"give a path, got {shown(value)}", source, field)
    if "\0" in value:
        raise InputError(f"a path cannot hold a NUL character: {shown(value)}", source, field)
    size = len(os.fsencode(value))
    if size > PATH_MAX:
        raise InputError(
            f"the path {shown(value)} is {size} bytes long; a path has at most {PATH_MAX}; "
            "give a shorter one",
            source,
            field,
        )
    for name in Path(value).parts:
        if len(os.fsencode(name)) > NAME_MAX:
            raise InputError(
                f"the name {shown(name)} in the path is {len(os.fsencode(name))} bytes long; a "
                f"file name has at most {NAME_MAX}; check the path",
                source,
                field,
            )
    return Path(value)


def input_file(
    value: object,
    base_dir: str | Path,
    source: str | Path | None,
    field: str | None,
    what: str = "file",
) -> Path:
    """The file ``value`` names (relative to ``base_dir`` unless absolute), checked: a path's
    form (`path_form`), present, a file and not a folder, readable. ``what`` names it in
    messages (e.g. "mesh file")."""
    path = path_form(value, source, field).expanduser()
    if not path.is_absolute():
        path = Path(base_dir) / path
    if path.is_dir():
        raise InputError(f"{shown(path)} is a folder; give the {what} in it", source, field)
    if not path.is_file():
        raise InputError(f"{what} not found: {shown(path)}; check the path", source, field)
    if not os.access(path, os.R_OK):
        raise InputError(
            f"{what} is not readable: {shown(path)}; check its permissions", source, field
        )
    return path


def output_path(
    value: object, field: str | None, folder: bool = False, source: str | Path | None = None
) -> Path:
    """``value`` checked as where an output goes: a path's form; no ``..`` after a folder that
    does not exist yet; a file output named (not ``..``) and not an existing folder, a
    ``folder`` output not an existing file; the nearest existing folder above it a folder (not
    a file) that can be written to."""
    path = path_form(value, source, field)
    for index, part in enumerate(path.parts):  # "new/.." needs "new", which is not there yet
        if part == ".." and not Path(*path.parts[:index] or ".").is_dir():
            raise InputError(
                f"{shown(path)} goes up (..) out of {shown(Path(*path.parts[:index]))}, which "
                "is not a folder; give the path without it",
                source,
                field,
            )
    if not folder and path.name in ("", ".."):  # pathlib drops a last "."
        raise InputError(f"{shown(path)} names a folder; give a file name", source, field)
    if folder and path.exists() and not path.is_dir():
        raise InputError(f"{shown(path)} is a file; give a folder for the outputs", source, field)
    if not folder and path.is_dir():
        raise InputError(f"{shown(path)} is a folder; give a file name", source, field)
    above = path if folder else path.parent
    absolute = Path(os.path.abspath(above))
    while not absolute.exists() and absolute != absolute.parent:
        absolute = absolute.parent
    if not absolute.is_dir():
        raise InputError(
            f"{shown(absolute)} is a file, so {shown(path)} cannot be written under it; give "
            "another path",
            source,
            field,
        )
    if not os.access(absolute, os.W_OK | os.X_OK):
        raise InputError(f"cannot write in {shown(absolute)}; check its permissions", source, field)
    return path
