"""The pattern a case's garment wears (`cloth.garment.cut`), from what the case names: built
once from the case before predeform (`case_cut`), and again from a state file's record for the
coarser levels of the error estimate and ``grid: auto`` (`state_cut`)."""

from __future__ import annotations

import json
from pathlib import Path

from cloth.case import Case
from cloth.files.body import body_from_config, body_from_record
from cloth.garment.cut import BodyCut, TableCut, read_pattern
from cloth.garment.state import State
from cloth.paths import input_file


def case_cut(
    case: Case, base_dir: str | Path, source: str = "case"
) -> tuple[BodyCut | TableCut | None, dict | None]:
    """The pattern of ``case``'s ``garment.pattern`` and, for a pattern cut for a body, that
    body's record (a state's ``pattern_body``); (None, None) for a garment cut on its wearer."""
    garment = case.garment
    block = garment.pattern
    if block is None:
        return None, None
    if "file" in block:
        path = input_file(block["file"], base_dir, source, "garment.pattern.file", "pattern file")
        return read_pattern(path), None
    span = (garment.bottom, garment.top)
    body, record = body_from_config(dict(block["body"]), base_dir, span, garment.loop_point)
    return BodyCut(body, garment, record.get("landmarks", {}), case.landmarks), record


def state_cut(state: State, case: Case | None = None) -> BodyCut | TableCut | None:
    """The pattern ``state``'s garment wears, from the state's record (`case_cut`); with
    ``case``, that case's garment cut on the same body (a design's new profile)."""
    garment = (state.case if case is None else case).garment
    if garment.pattern is None:
        return None
    if "pattern_table" in state.attrs:
        return TableCut.from_attr(json.loads(state.attrs["pattern_table"]))
    record = json.loads(state.attrs["pattern_body"])
    body = body_from_record(record)
    return BodyCut(body, garment, record.get("landmarks", {}), state.case.landmarks)


__all__ = ["case_cut", "state_cut"]
