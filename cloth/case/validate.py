"""Case files: load, validate against the JSON Schema, fill defaults (`cloth.case.case` types
them: `validate_case`, `load_case`, `Case.load`, `Case.of`).

One simulation = one YAML case (schema: ``cloth/schemas/case.schema.yaml``, documented in
docs/config.md). Errors name the file and the key path, e.g.
``case.yaml: garment.reduction: 1.2 is greater than or equal to the maximum of 0.9``.
"""

from __future__ import annotations

import copy
import math
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import yaml

from cloth.errors import InputError
from cloth.paths import shown

#: The body kinds a case's ``body`` block names one of.
BODY_KINDS = ("mesh", "avatar", "torso", "leg", "cylinder", "elliptic_cylinder", "cone")
MESH_ONLY = (
    "units",
    "up",
    "repair",
    "surface",
    "smoothing",
    "spacing",
    "surface_file",
    "kind",
    "region",
)
#: Of those, the keys an avatar takes too (its mesh is metres, z up, closed, and knows its kind).
AVATAR_TOO = ("surface", "smoothing", "spacing", "surface_file", "region")
#: The garment keys that may be a profile (`cloth.case.profile`).
PROFILE_KEYS = ("reduction", "lengthwise_reduction")


def _finite_number(checker: Any, instance: Any) -> bool:
    """JSON Schema's number, finite: YAML's .inf and .nan are not numbers a case can mean."""
    number = jsonschema.Draft202012Validator.TYPE_CHECKER.is_type(instance, "number")
    return number and (not isinstance(instance, float) or math.isfinite(instance))


#: The case's validator: Draft 2020-12 whose numbers are finite. Where infinity means something,
#: a schema says so with ``const: .inf`` beside the number (and a description of its meaning).
Validator = jsonschema.validators.extend(
    jsonschema.Draft202012Validator,
    type_checker=jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("number", _finite_number),
)


def schema_message(error: jsonschema.ValidationError) -> str:
    """A validation error's message in one line, the value shortened, with its fix."""
    value = error.instance
    if isinstance(value, float) and not math.isfinite(value):
        return f"{value} is not a finite number; give a finite value (docs/config.md)"
    branch = _branch_of(error)
    if branch is not None:
        return schema_message(branch)
    message = error.message
    if error.validator == "type" and isinstance(value, str) and _number_text(value):
        return (
            f"{value!r} is text to YAML, not a number; write it with a dot and a signed "
            "exponent, e.g. 1.0e+9"
        )
    if isinstance(value, (str, list, dict)) and len(repr(value)) > 80:
        message = message.replace(repr(value), shown(value))
    if len(message) > 300:
        message = f"{message[:200]}... ({len(message)} characters)"
    if error.validator == "additionalProperties":
        message += "; check the spelling against docs/config.md"
    if error.validator == "oneOf" and "description" in error.schema:
        message = f"{shown(value)} is not one of the forms asked: {error.schema['description']}"
    return " ".join(message.split())


def _branch_of(error: jsonschema.ValidationError) -> jsonschema.ValidationError | None:
    """Of a ``oneOf`` the value failed, the branch of the value's own type that it failed
    (``reduction: 1.2`` is a number too big, not a wrong form), else None: where the value
    matches no branch's type, or only a constant's (``grid: aut``), the forms are described."""
    if error.validator != "oneOf" or not error.context:
        return None
    same_type = [
        e
        for e in error.context
        if not (e.validator in ("type", "const", "enum") and not e.relative_path)
    ]
    branches = {e.relative_schema_path[0] for e in error.context if e.relative_schema_path}
    wrong_type = {
        e.relative_schema_path[0]
        for e in error.context
        if e.validator == "type" and not e.relative_path and e.relative_schema_path
    }
    return same_type[0] if same_type and len(branches - wrong_type) == 1 else None


def _number_text(text: str) -> bool:
    """Whether ``text`` reads as a number (YAML 1.1 reads 1e9 as text, 1.0e+9 as a number)."""
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


@cache
def case_schema() -> dict[str, Any]:
    text = resources.files("cloth").joinpath("schemas/case.schema.yaml").read_text()
    return yaml.safe_load(text)


def _key_path(error: jsonschema.ValidationError) -> str:
    return ".".join(str(part) for part in error.absolute_path) or "(top level)"


def _fill_defaults(schema: dict[str, Any], data: Any) -> None:
    """Set the schema's defaults on missing keys of nested objects, and of the objects in
    arrays (a garment's bands, panels and layers), in place."""
    if isinstance(data, list) and isinstance(schema.get("items"), dict):
        for item in data:
            _fill_defaults(schema["items"], item)
        return
    if not isinstance(data, dict):
        return
    for key, sub in schema.get("properties", {}).items():
        if key not in data and "default" in sub:
            data[key] = copy.deepcopy(sub["default"])
        if key in data:
            _fill_defaults(sub, data[key])


def checked_mapping(case: Any, source: str | Path = "case") -> dict[str, Any]:
    """A case mapping checked against the schema and its defaults filled: what
    `cloth.case.case.validate_case` builds the typed `Case` from (which then checks what each
    block's type knows). Raises `InputError` naming ``source`` and the key path of the first
    problem.
    """
    if not isinstance(case, dict):
        raise InputError("a case must be a mapping of keys to values", source)
    case = _text_keys(case)
    errors = sorted(
        Validator(case_schema()).iter_errors(case),
        key=lambda e: (len(e.absolute_path), [str(part) for part in e.absolute_path]),
    )
    if errors:
        raise InputError(schema_message(errors[0]), source, _key_path(errors[0]))
    kinds = _check_body(case["body"], source, "body")
    pattern = case["garment"].get("pattern")
    if pattern is not None:
        if ("body" in pattern) == ("file" in pattern):
            raise InputError(
                "give exactly one of body (the body the pattern is cut for) or file (a "
                "pattern.csv that cloth pattern wrote)",
                source,
                "garment.pattern",
            )
        if "body" in pattern:
            _check_body(pattern["body"], source, "garment.pattern.body")
    garment = case["garment"]
    if pattern is not None and "file" in pattern:
        given = [key for key in ("reduction", "circumference") if key in garment]
        if garment.get("lengthwise_reduction", 0.0) != 0.0:
            given.append("lengthwise_reduction")
        if given:
            raise InputError(
                f"a pattern file holds the rows' rest lengths; remove {given[0]}",
                source,
                f"garment.{given[0]}",
            )
    elif ("reduction" in garment) == ("circumference" in garment):
        raise InputError(
            "give exactly one of reduction (graded pattern) or circumference (rectangle)",
            source,
            "garment",
        )
    if garment["bottom"] >= garment["top"]:
        raise InputError(
            f"bottom ({garment['bottom']} m) must be below top ({garment['top']} m)",
            source,
            "garment.bottom",
        )
    if garment["grid"] == "auto":
        pass
    elif "accuracy" in garment or "max_nodes" in garment:
        key = "accuracy" if "accuracy" in garment else "max_nodes"
        raise InputError(
            f"{key} refines an automatic grid; give grid: auto, or drop {key} (an explicit "
            "grid reports its own error estimate)",
            source,
            f"garment.{key}",
        )
    elif garment["grid"][0] < 3 or garment["grid"][1] < 2:
        n, m = garment["grid"]
        raise InputError(
            f"grid {n} x {m} is too small; a tube needs at least 3 nodes around and 2 up",
            source,
            "garment.grid",
        )
    case.setdefault("solver", {})
    _fill_defaults(case_schema(), case)
    if case["garment"]["grid"] != "auto":  # the automatic grid's keys: not an explicit grid's
        for key in AUTO_GRID_KEYS:
            case["garment"].pop(key, None)
    _body_defaults(case["body"], kinds[0])
    if pattern is not None and "body" in pattern:
        _body_defaults(pattern["body"], _check_body(pattern["body"], source, "")[0])
    return case


#: The garment keys of ``grid: auto`` alone: their defaults are filled for it only.
AUTO_GRID_KEYS = ("accuracy", "max_nodes")


def _check_body(body: dict[str, Any], source: str | Path, field: str) -> list[str]:
    """The kinds of a body block (exactly one, else `InputError` at ``field``), its mesh-only
    keys checked."""
    kinds = [kind for kind in BODY_KINDS if kind in body]
    if len(kinds) != 1:
        raise InputError(
            f"give exactly one of {', '.join(BODY_KINDS)} (found {', '.join(kinds) or 'none'})",
            source,
            field,
        )
    if kinds[0] != "mesh":
        allowed = AVATAR_TOO if kinds[0] == "avatar" else ()
        extra = [key for key in MESH_ONLY if key in body and key not in allowed]
        if extra:
            only = "mesh and avatar bodies" if extra[0] in AVATAR_TOO else "mesh bodies"
            raise InputError(f"{extra[0]} applies to {only} only; remove it", source, field)
    return kinds


def _body_defaults(body: dict[str, Any], kind: str) -> None:
    """A body block's mesh keys: their defaults for a mesh or avatar, none for another kind."""
    keep = MESH_ONLY if kind == "mesh" else AVATAR_TOO if kind == "avatar" else ()
    for key in MESH_ONLY:
        if key not in keep:  # the schema's defaults, filled for every kind: not this one's
            body.pop(key, None)
    for key in keep:
        spec = case_schema()["properties"]["body"]["properties"][key]
        if "default" in spec:
            body.setdefault(key, spec["default"])


def _text_keys(case: dict[str, Any]) -> dict[str, Any]:
    """A copy of ``case`` whose profiles' keys are text: YAML reads a height key (``1.05:``) as
    a number, and JSON (state files) writes every key as text."""
    case = copy.deepcopy(case)
    garment = case.get("garment")
    if isinstance(garment, dict):
        for key in PROFILE_KEYS:
            if isinstance(garment.get(key), dict):
                garment[key] = {str(k): v for k, v in garment[key].items()}
    return case


def read_mapping(path: str | Path) -> dict[str, Any]:
    """A YAML case file's mapping, checked (`checked_mapping`); `InputError` naming the file."""
    path = Path(path)
    if not path.is_file():
        raise InputError("case file not found; check the path", path)
    try:
        case = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark else None
        raise InputError(f"not valid YAML ({getattr(exc, 'problem', exc)})", path, where) from None
    return checked_mapping(case, path)
