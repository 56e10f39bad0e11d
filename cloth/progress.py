"""Progress of long steps: a tqdm bar on a terminal, log lines otherwise (a Snakemake job's log,
a cluster job), so that long work is never silent."""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Iterable, Iterator

from tqdm import tqdm

log = logging.getLogger(__name__)

#: Off a terminal, a log line at most this often (s), and at every tenth of the work.
LOG_SECONDS = 30.0


class LogProgress:
    """What tqdm offers the library (``update``, iteration, a context), as log lines: at every
    tenth of ``total`` and at most every `LOG_SECONDS`, with the rate and the time left."""

    def __init__(self, iterable: Iterable | None, total: int, desc: str, unit: str) -> None:
        self.iterable, self.total, self.desc, self.unit = iterable, max(int(total), 1), desc, unit
        self.done = 0
        self.start = self.last = time.perf_counter()
        self.tenth = 0

    def update(self, count: int = 1) -> None:
        self.done += count
        now = time.perf_counter()
        tenth = 10 * self.done // self.total
        if tenth > self.tenth or now - self.last >= LOG_SECONDS:
            self.tenth, self.last = tenth, now
            rate = self.done / max(now - self.start, 1e-9)
            log.info(
                "%s: %d %% (%s of %s %s, %.3g %s/s, %.0f s left)",
                self.desc,
                100 * self.done // self.total,
                f"{self.done:,}",
                f"{self.total:,}",
                self.unit,
                rate,
                self.unit,
                (self.total - self.done) / rate,
            )

    def __iter__(self) -> Iterator:
        for item in () if self.iterable is None else self.iterable:
            yield item
            self.update()

    def __enter__(self) -> LogProgress:
        return self

    def __exit__(self, *exc) -> None:
        return None

    def close(self) -> None:
        return None


def progress(
    iterable: Iterable | None = None,
    total: int | None = None,
    desc: str = "",
    unit: str = "it",
    show: bool | None = None,
):
    """A progress reporter over ``iterable`` (or ``total`` units, advanced with ``update``):
    ``show`` True a tqdm bar, False nothing, None a bar on a terminal and log lines otherwise."""
    if total is None and iterable is not None:
        total = len(iterable)  # type: ignore[arg-type]
    if show is None and not sys.stderr.isatty():
        return LogProgress(iterable, total or 0, desc, unit)
    return tqdm(
        iterable,
        total=total,
        desc=desc,
        unit=unit,
        disable=show is False,
        mininterval=1.0,
        leave=False,
    )
