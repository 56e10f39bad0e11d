"""Reading a PDF the tests wrote back: its page boxes, its content streams, the squares drawn."""

from __future__ import annotations

import re
import zlib
from pathlib import Path

import numpy as np


def pdf_pages(path: Path) -> tuple[list[list[float]], list[bytes]]:
    """The PDF's page boxes (pt) and its content streams, decompressed."""
    data = path.read_bytes()
    boxes = [
        [float(v) for v in m.split()] for m in re.findall(rb"/MediaBox \[ ?([^\]]*?) ?\]", data)
    ]
    streams = []
    for raw in re.findall(rb"stream\r?\n(.*?)\r?\nendstream", data, re.S):
        try:
            streams.append(zlib.decompress(raw))
        except zlib.error:
            streams.append(raw)
    return boxes, streams


def squares(stream: bytes) -> list[float]:
    """Sides (pt) of the closed four-corner axis-aligned paths drawn in ``stream``."""
    sides = []
    for path in re.findall(rb"((?:[-\d.]+ [-\d.]+ [ml]\s+){5})h", stream):
        points = np.array([[float(v) for v in p.split()[:2]] for p in path.strip().splitlines()])
        w, h = np.ptp(points[:, 0]), np.ptp(points[:, 1])
        if np.allclose(points[0], points[-1]) and abs(w - h) < 1e-6:
            sides.append(float(w))
    return sides
