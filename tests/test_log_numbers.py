"""Numbers in the log (issue 71, item 3): every number a command logs at CI size has sensible
digits - a decimal number at most `DIGITS` significant digits (no float printed whole, as
"share 0.8519454610606568" was) - read from the log lines the commands write."""

from __future__ import annotations

import logging
import re

import pytest
import yaml

from cloth.cli import main

#: Significant digits a logged decimal number may have.
DIGITS = 6
#: A decimal number in text: digits with a point, optionally an exponent.
DECIMAL = re.compile(r"(?<![\w.])-?(\d+\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
CONE = {
    "material": "powernet",
    "body": {"cone": {"radius_bottom": 0.13, "radius_top": 0.09, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [24, 12]},
    "landmarks": {"low": 0.2, "high": 0.3},
    "judge": {"class_point": "low"},
}


def too_long(message: str) -> list[str]:
    """The decimal numbers of ``message`` with more than `DIGITS` significant digits (a path's
    digits are not numbers: words and paths are left out)."""
    words = [w for w in message.split() if "/" not in w]
    found = []
    for match in DECIMAL.finditer(" ".join(words)):
        digits = match.group(1).replace(".", "").lstrip("0")
        if len(digits) > DIGITS:
            found.append(match.group(0))
    return found


def test_the_rule_sees_a_float_printed_whole():
    assert too_long("waist: share 0.8519454610606568") == ["0.8519454610606568"]
    assert too_long("pressure 2.34e+03 Pa, 41,472 nodes, in /tmp/pytest-1/x0.123456789") == []


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """Every log line of cloth run, cloth pattern and cloth compare on a cone at CI size."""
    folder = tmp_path_factory.mktemp("logs")
    case = folder / "case.yaml"
    case.write_text(yaml.safe_dump(CONE))
    readings = folder / "readings.csv"
    readings.write_text(
        "point,height_m,angle_deg,pressure_mmHg,probe_mm,repeat\nlow,,90,12,50,1\n,0.25,0,11,50,1\n"
    )
    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            records.append(record)

    keep = Keep(logging.INFO)
    root = logging.getLogger("cloth")
    level = root.level
    root.setLevel(logging.INFO)  # what the command's --log-level INFO (its default) logs
    root.addHandler(keep)
    try:
        out = folder / "out"
        assert main(["run", str(case), "-o", str(out)]) == 0
        result = str(out / "result.nc")
        assert main(["pattern", result, "-o", str(folder / "p" / "pattern.csv")]) == 0
        assert main(["compare", result, str(readings), "-o", str(folder / "c")]) == 0
    finally:
        root.removeHandler(keep)
        root.setLevel(level)
    return [r.getMessage() for r in records]


def test_every_logged_number_has_sensible_digits(logged):
    assert len(logged) > 10
    bad = {line: too_long(line) for line in logged if too_long(line)}
    assert bad == {}


def test_the_judged_share_is_a_share_of_the_class_point(logged):
    shares = [line for line in logged if "share" in line and "class point" in line]
    assert shares, logged
