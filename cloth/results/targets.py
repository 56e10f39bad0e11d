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
    """A girth line's target mean pressure, Pa; or a band (``low``, ``high``, Pa), whose
    centre is ``pressure`` (a robust design puts every wearer inside it)."""

    line: str
    pressure: float
    band: tuple[float, float] | None = None

    @classmethod
    def parse(cls, text: str, field: str = "--target") -> Target:
        """``waist=20`` (mmHg), ``waist=20mmHg``, ``waist=2.6kPa`` or ``waist=2600Pa``; a band
        ``B=23:32`` (low:high, one unit for both, e.g. ``B=3.1:4.3kPa``)."""
        band = re.fullmatch(
            r"\s*([^=\s]+)\s*=\s*([-+0-9.eE]+)\s*:\s*([-+0-9.eE]+)\s*(mmHg|kPa|Pa)?\s*", text
        )
        if band:
            try:
                low, high = float(band.group(2)), float(band.group(3))
            except ValueError:
                low = high = float("nan")
            if not (np.isfinite(low) and np.isfinite(high) and 0 < low < high):
                raise InputError(
                    f"{text!r} is not a band; write LINE=LOW:HIGH with 0 < LOW < HIGH in mmHg "
                    "(default), kPa or Pa, e.g. B=23:32",
                    field=field,
                )
            scale = UNITS[(band.group(4) or "mmHg").lower()]
            return cls(band.group(1), 0.5 * (low + high) * scale, (low * scale, high * scale))
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


def config_targets(texts: list[str], where: str) -> list[Target]:
    """The targets of a pipeline config's list ``texts`` (`Target.parse`), the one refused
    named by its config key ``{where}.{number}``."""
    out = []
    for number, text in enumerate(texts):
        try:
            out.append(Target.parse(text))
        except InputError as exc:
            raise InputError(exc.detail, "config", f"{where}.{number}") from None
    return out
