"""Strategies of bad input for the property-based tests (tests/test_fuzz.py): mutations of a
valid case, drawn from the case's schema so that a field added to it is fuzzed without anyone
remembering to, and corruptions of the example lab table and of a mesh file.

A mutation drops a key, puts a value of another kind (None, booleans, wrong types, NaN,
infinities, huge, tiny and negative numbers, long strings, unknown keys) at a key the schema
knows or at one it does not, nests a block where another belongs, or scales a number the case
has (zero, negative, tiny, huge: the same type, so it reaches the checks behind the schema).
"""

from __future__ import annotations

import copy
import itertools
from typing import Any

from hypothesis import strategies as st

from cloth.case.validate import case_schema

#: A valid case on a tiny grid (24 nodes): it runs every stage in about a second.
TINY = {
    "material": "powernet",
    "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [8, 3]},
    "solver": {"max_iterations": 60},
}
#: Values a typo or a wrong paste puts in a case.
ODD = [
    None,
    True,
    False,
    0,
    -1,
    1,
    2,
    3,
    10**9,
    -(10**9),
    1e308,
    -1e308,
    1e-308,
    -1e-9,
    0.5,
    1.5,
    float("nan"),
    float("inf"),
    float("-inf"),
    "",
    " ",
    "x" * 5000,
    "powernet",
    "m",
    "..",
    "/dev/null",
    "/",
    "a\0b",
    "é",
    [],
    [1],
    [1, 2],
    [1, 2, 3],
    [0.1, "a"],
    {},
    {"unknown": 1},
]


def schema_paths(schema: dict[str, Any], prefix: tuple = ()) -> list[tuple]:
    """Every key path the schema describes (objects' properties, an array's first item)."""
    paths = []
    for key, sub in schema.get("properties", {}).items():
        path = (*prefix, key)
        paths.append(path)
        paths.extend(schema_paths(sub, path))
        items = sub.get("items")
        if isinstance(items, dict) and items.get("type") == "object":
            paths.extend(schema_paths(items, (*path, 0)))
    return paths


def present_paths(data: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key path in ``data`` (dict keys and list indices)."""
    paths = []
    items = (
        data.items()
        if isinstance(data, dict)
        else enumerate(data)
        if isinstance(data, list)
        else ()
    )
    for key, value in items:
        paths.append((*prefix, key))
        paths.extend(present_paths(value, (*prefix, key)))
    return paths


def _put(data: dict, path: tuple, value: Any) -> None:
    """Set ``path`` in ``data`` to ``value``, making the containers on the way."""
    node: Any = data
    for key, following in itertools.pairwise(path):
        kind = list if isinstance(following, int) else dict
        if isinstance(node, list):
            while len(node) <= key:
                node.append(None)
        if not isinstance(node[key] if isinstance(node, list) else node.get(key), kind):
            node[key] = kind()
        node = node[key]
    if isinstance(node, list):
        while len(node) <= path[-1]:
            node.append(None)
    node[path[-1]] = value


def _drop(data: dict, path: tuple) -> None:
    node: Any = data
    for key in path[:-1]:
        node = node[key]
    del node[path[-1]]


#: Factors a numeric value is scaled by: zero, a flipped sign, tiny, a little, huge.
SCALES = [0, -1, 1e-9, 1e-3, 0.5, 0.9, 1.1, 2, 10, 1e3, 1e9]


def _get(data: Any, path: tuple) -> Any:
    for key in path:
        data = data[key]
    return data


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


SCHEMA_PATHS = schema_paths(case_schema())
BLOCKS = ("material", "body", "garment", "contact", "landmarks", "solver")


@st.composite
def mutation(draw: st.DrawFn, case: dict) -> tuple:
    """One change to ``case`` (applied by `mutate`)."""
    kind = draw(st.sampled_from(["put", "put", "drop", "unknown", "nest", "scale", "scale"]))
    if kind == "scale":  # the same kind of value, another size: passes the schema more often
        numbers = [p for p in present_paths(case) if _is_number(_get(case, p))]
        if numbers:
            path = draw(st.sampled_from(numbers))
            factor = draw(st.sampled_from(SCALES))
            value = _get(case, path) * factor
            return ("put", path, int(value) if isinstance(_get(case, path), int) else value)
    if kind == "drop":
        paths = present_paths(case)
        return ("drop", draw(st.sampled_from(paths))) if paths else ("put", ("material",), None)
    if kind == "unknown":
        parent = draw(
            st.sampled_from([(), *[p for p in SCHEMA_PATHS if not isinstance(p[-1], int)]])
        )
        return ("put", (*parent, draw(st.sampled_from(["colour", "Grid", "toleranse"]))), 1)
    if kind == "nest":
        inner, outer = draw(st.sampled_from(BLOCKS)), draw(st.sampled_from(BLOCKS))
        return ("put", (outer, inner), copy.deepcopy(TINY.get(inner, {"a": 1})))
    value = draw(st.one_of(st.sampled_from(ODD), st.floats(), st.integers(), st.text(max_size=8)))
    return ("put", draw(st.sampled_from(SCHEMA_PATHS)), value)


def mutate(case: dict, change: tuple) -> dict:
    out = copy.deepcopy(case)
    if change[0] == "drop":
        try:
            _drop(out, change[1])
        except (KeyError, IndexError, TypeError):
            pass
    else:
        _put(out, change[1], change[2])
    return out


@st.composite
def bad_cases(draw: st.DrawFn) -> dict:
    """The tiny case with one to three mutations."""
    case = copy.deepcopy(TINY)
    for _ in range(draw(st.integers(1, 3))):
        case = mutate(case, draw(mutation(case)))
    return case


@st.composite
def corrupted_text(draw: st.DrawFn, text: str) -> str:
    """``text`` (a lab table or an ASCII mesh) with one to three corruptions: a line dropped,
    doubled or cut short, a field replaced by an odd value, the file truncated, bytes of
    garbage put in."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, 3))):
        if not lines:
            break
        kind = draw(st.sampled_from(["drop", "double", "cut", "field", "truncate", "garbage"]))
        i = draw(st.integers(0, len(lines) - 1))
        if kind == "drop":
            del lines[i]
        elif kind == "double":
            lines.insert(i, lines[i])
        elif kind == "cut":
            lines[i] = lines[i][: draw(st.integers(0, max(len(lines[i]) - 1, 0)))]
        elif kind == "field":
            sep = "," if "," in lines[i] else " "
            fields = lines[i].split(sep)
            j = draw(st.integers(0, len(fields) - 1))
            fields[j] = draw(
                st.sampled_from(
                    ["", "nan", "inf", "-inf", "x", "1e400", "-5", "0", "1,2", '"', "\t"]
                )
            )
            lines[i] = sep.join(fields)
        elif kind == "truncate":
            lines = lines[:i]
        else:
            lines.insert(i, draw(st.text(max_size=30)))
    return "\n".join(lines) + ("\n" if draw(st.booleans()) else "")


#: Pieces of paths as users type them, and some no file system takes.
PATH_PARTS = [
    "out.ply",
    "a_file",
    "a_folder",
    "new",
    "..",
    ".",
    "",
    " ",
    "x" * 300,
    "caf\u00e9.ply",
    "a\0b.ply",
    "sp ace.ply",
    "-o",
]


@st.composite
def odd_paths(draw: st.DrawFn) -> str:
    """A relative path of one to three odd pieces (an empty one is the empty path)."""
    parts = draw(st.lists(st.sampled_from(PATH_PARTS), min_size=1, max_size=3))
    return "/".join(parts).strip("/") if any(parts) else ""


@st.composite
def odd_targets(draw: st.DrawFn) -> str:
    """``--target`` text: a line name (or none), ``=`` (or not), a number as users and
    programs write them (or not one), a unit (or a wrong one)."""
    line = draw(st.sampled_from(["waist", "hip", "", " ", "0.25", "a b", "B1", "=", "w\u00e4ist"]))
    sign = draw(st.sampled_from(["=", "", "==", " = "]))
    number = draw(
        st.one_of(
            st.sampled_from(["20", "1e400", "inf", "nan", "-3", "0", "1e-300", "", "2.0.0", "x"]),
            st.floats(allow_nan=True, allow_infinity=True).map(repr),
        )
    )
    unit = draw(st.sampled_from(["", "mmHg", "kPa", "Pa", "psi", " mmHg", "MMHG"]))
    return f"{line}{sign}{number}{unit}"
