"""Agreement between the model and measured readings: Bland and Altman's statistics.

Repeats first: readings at one place (a subject, a height, an angle and a probe) are averaged
(`average_repeats`), and their spread is the measurement's own noise, pooled over the places
that have repeats (`pooled_sd`: sqrt(sum (k_i - 1) s_i^2 / sum (k_i - 1)), s_i the sample
standard deviation of place i's k_i readings).

Then, over the places, with d = model - measured (`Agreement.of`): the bias (mean of d), the
standard deviation of d (n - 1 in the denominator), the limits of agreement bias +- 1.96 sd
(Bland and Altman 1986, where 95 % of differences are expected), the root mean square of d and
Pearson's r between model and measured (NaN with fewer than 3 places or no spread,
`SPREAD`). Units are
the readings' (Pa in the library; the files write mmHg).
"""

from __future__ import annotations

import math
from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: The limits of agreement are bias +- this many standard deviations (95 %).
LOA_Z = 1.96
#: Values whose standard deviation is below this share of their mean have no spread (a
#: uniform pressure read at several places differs by rounding): r is then not defined.
SPREAD = 1e-9


@dataclass(frozen=True)
class Averaged:
    """Readings averaged over repeats: ``first`` (P,) the index of each place's first reading,
    ``mean`` (P,), ``sd`` (P,) (NaN for a single reading) and ``count`` (P,)."""

    first: NDArray[np.int64]
    mean: NDArray[np.float64]
    sd: NDArray[np.float64]
    count: NDArray[np.int64]


def average_repeats(keys: Sequence[Hashable], values: NDArray[np.float64]) -> Averaged:
    """The mean, sample standard deviation and count of ``values`` (R,) per distinct key of
    ``keys`` (R; a place), in the order keys first appear."""
    groups: dict[Hashable, list[int]] = {}
    for k, key in enumerate(keys):
        groups.setdefault(key, []).append(k)
    members = list(groups.values())
    mean = np.array([values[m].mean() for m in members])
    sd = np.array([values[m].std(ddof=1) if len(m) > 1 else np.nan for m in members])
    count = np.array([len(m) for m in members], dtype=np.int64)
    return Averaged(np.array([m[0] for m in members], dtype=np.int64), mean, sd, count)


def pooled_sd(count: NDArray[np.int64], sd: NDArray[np.float64]) -> float:
    """The repeats' pooled standard deviation (module docstring) of places with ``count`` (P,)
    readings whose sample standard deviations are ``sd`` (P,); NaN where no place has
    repeats."""
    dof = count - 1
    has = (dof > 0) & np.isfinite(sd)
    if not has.any():
        return float("nan")
    return math.sqrt(float(np.sum(dof[has] * sd[has] ** 2) / np.sum(dof[has])))


@dataclass(frozen=True)
class Agreement:
    """Bland-Altman statistics of model against measured (module docstring): ``n`` places,
    ``bias``, ``sd``, ``loa_low``, ``loa_high``, ``rmse`` (the readings' units) and ``r`` (1)."""

    n: int
    bias: float
    sd: float
    loa_low: float
    loa_high: float
    rmse: float
    r: float

    @classmethod
    def of(cls, model: NDArray[np.float64], measured: NDArray[np.float64]) -> Agreement:
        """The statistics of ``model`` against ``measured`` ((P,) each, one unit); places
        where either is NaN are left out."""
        keep = np.isfinite(model) & np.isfinite(measured)
        a, b = model[keep], measured[keep]
        n = int(a.size)
        if n == 0:
            nan = float("nan")
            return cls(0, nan, nan, nan, nan, nan, nan)
        d = a - b
        bias = float(d.mean())
        sd = float(d.std(ddof=1)) if n > 1 else float("nan")
        rmse = float(np.sqrt(np.mean(d * d)))
        spread = n >= 3 and all(
            v.std() > SPREAD * max(abs(float(v.mean())), 1e-300) for v in (a, b)
        )
        r = float(np.corrcoef(a, b)[0, 1]) if spread else float("nan")
        return cls(n, bias, sd, bias - LOA_Z * sd, bias + LOA_Z * sd, rmse, r)


@dataclass(frozen=True)
class Compared:
    """Readings averaged over repeats, one entry per place (P,): ``subject``, ``point`` (the
    girth line it was named by, or ''), ``height`` m, ``angle`` degrees, ``probe`` m,
    ``repeats``, ``measured`` Pa (mean of the repeats), ``repeat_sd`` Pa (NaN for one reading),
    ``model`` Pa, ``model_error`` Pa (NaN where none is stated), ``error_line`` (the girth line
    the error is taken from)."""

    subject: tuple[str, ...]
    point: tuple[str, ...]
    height: NDArray[np.float64]
    angle: NDArray[np.float64]
    probe: NDArray[np.float64]
    repeats: NDArray[np.int64]
    measured: NDArray[np.float64]
    repeat_sd: NDArray[np.float64]
    model: NDArray[np.float64]
    model_error: NDArray[np.float64]
    error_line: tuple[str, ...]

    @property
    def difference(self) -> NDArray[np.float64]:
        """(P,) Pa: model - measured."""
        return self.model - self.measured

    def of_subject(self, name: str) -> Compared:
        """The places of one subject."""
        keep = np.array([s == name for s in self.subject], dtype=bool)
        return _select(self, keep)

    @classmethod
    def joined(cls, parts: list[Compared]) -> Compared:
        """The places of ``parts`` one after the other (a study's subjects)."""
        fields = cls.__dataclass_fields__
        values = {}
        for name in fields:
            items = [getattr(p, name) for p in parts]
            if isinstance(items[0], tuple):
                values[name] = tuple(v for item in items for v in item)
            else:
                values[name] = np.concatenate(items)
        return cls(**values)


def _select(table: Compared, keep: NDArray[np.bool_]) -> Compared:
    values = {}
    for name in Compared.__dataclass_fields__:
        item = getattr(table, name)
        if isinstance(item, tuple):
            values[name] = tuple(v for v, k in zip(item, keep, strict=True) if k)
        else:
            values[name] = item[keep]
    return Compared(**values)
