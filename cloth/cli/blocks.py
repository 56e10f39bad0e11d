"""A command's options from a JSON block (``--json``): a config's material block for
``cloth material ingest``, a case's body block for ``cloth body torso``, ``fit`` and ``check``.

A block's key is its option's name (``thickness_mm`` is ``--thickness-mm``, ``directions`` is
``--direction`` repeated, ``table`` the tables), so the option names are declared once, in the
parser, and the workflow hands its blocks over as they are, as ``cloth case write`` takes a case.
Each value is converted and checked as the option's own would be. A key that is also given on
the line, or that the command does not know, is refused in one line naming it.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from cloth.errors import InputError

#: Block keys whose option has another name.
RENAMED = {"table": "tables", "directions": "direction"}
#: Options that are a command's outputs, not a block's keys.
OUTPUTS = frozenset({"block", "output", "plot", "curvature", "help"})
#: Where a body command finds its options: a torso block's are in its ``torso`` sub-block.
NESTED = ("torso",)


def apply_block(
    parser: argparse.ArgumentParser, args: argparse.Namespace, ignore: frozenset[str] = frozenset()
) -> None:
    """Set the options of ``args`` (parsed by ``parser``) from the JSON block ``args.block``;
    keys in ``ignore`` are the block's but not this command's business (a case's tissue)."""
    block = _parse(args.block)
    for key in NESTED:
        if isinstance(block.get(key), dict):
            block = {**{k: v for k, v in block.items() if k != key}, **block[key]}
    actions = {a.dest: a for a in parser._actions if a.dest not in OUTPUTS}
    for key, value in block.items():
        action = actions.get(RENAMED.get(key, key))
        if action is None:
            if key in ignore:
                continue
            names = {dest: key for key, dest in RENAMED.items()}
            known = sorted(names.get(dest, dest) for dest in actions)
            raise InputError(
                f"{key!r} is not an option of this command; use {', '.join(known)}",
                "--json",
                key,
            )
        if getattr(args, action.dest) not in (None, [], action.default):
            raise InputError(
                f"{key} is given both in --json and on the command line; give it once",
                "--json",
                key,
            )
        setattr(args, action.dest, _convert(action, key, value))


def _parse(text: str) -> dict[str, Any]:
    try:
        block = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"not valid JSON ({exc.msg})", field="--json") from None
    if not isinstance(block, dict):
        raise InputError("give a JSON object of option names and values", field="--json")
    return block


def _convert(action: argparse.Action, key: str, value: Any) -> Any:
    if action.nargs == 0 or isinstance(action, argparse.BooleanOptionalAction):
        if not isinstance(value, bool):
            raise InputError(f"must be true or false, got {value!r}", "--json", key)
        return value
    if (
        isinstance(action, argparse._AppendAction)
        or action.nargs in ("+", "*")
        or isinstance(action.nargs, int)
    ):
        values = value if isinstance(value, list) else [value]
        if isinstance(action.nargs, int) and len(values) != action.nargs:
            raise InputError(f"give {action.nargs} values, got {value!r}", "--json", key)
        return [_one(action, key, item) for item in values]
    return _one(action, key, value)


def _one(action: argparse.Action, key: str, value: Any) -> Any:
    if isinstance(value, (dict, list, bool)) or value is None:
        raise InputError(f"must be a single number or text, got {value!r}", "--json", key)
    if action.type is not None:
        try:
            value = action.type(value if isinstance(value, (int, float)) else str(value))
        except (TypeError, ValueError, argparse.ArgumentTypeError) as exc:
            raise InputError(f"{value!r} is not valid ({exc})", "--json", key) from None
    if action.choices is not None and value not in action.choices:
        raise InputError(
            f"{value!r} is not one of {', '.join(map(str, action.choices))}", "--json", key
        )
    return value
