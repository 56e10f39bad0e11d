"""A design target: a girth line's mean pressure, read as ``LINE=PRESSURE`` (``cloth design
--target``, the pipeline's ``profile_designs`` targets)."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from cloth.errors import InputError
from cloth.results.pressure import MMHG

#: Pressure units a target may be given in, Pa each.
UNITS = {"mmhg": MMHG, "kpa": 1e3, "pa": 1.0}


@dataclass(frozen=True)
class Target:
    """A girth line's target mean pressure, Pa."""

    line: str
    pressure: float

    @classmethod
    def parse(cls, text: str, field: str = "--target") -> Target:
        """``waist=20`` (mmHg), ``waist=20mmHg``, ``waist=2.6kPa`` or ``waist=2600Pa``."""
        match = re.fullmatch(r"\s*([^=\s]+)\s*=\s*([-+0-9.eE]+)\s*(mmHg|kPa|Pa)?\s*", text)
        try:
            value = float(match.group(2)) if match else float("nan")
        except ValueError:
            value = float("nan")
        if not match or not np.isfinite(value) or value <= 0:
            raise InputError(
                f"{text!r} is not a target; write LINE=PRESSURE with a positive pressure in "
                "mmHg (default), kPa or Pa, e.g. waist=20 or hip=2.0kPa",
                field=field,
            )
        unit = (match.group(3) or "mmHg").lower()
        return cls(match.group(1), value * UNITS[unit])
