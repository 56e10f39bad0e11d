"""What a case's cluster jobs ask for (cloth/pipeline/resources.py) covers what they use."""

from __future__ import annotations

import sys

import pytest
import yaml

from cloth.case.case import validate_case
from cloth.pipeline.resources import measure_stage, stage_resources
from tests.pipeline import ROOT


def peak_mib(*args: str) -> float:
    """Peak resident memory of ``cloth ARGS`` as its own process, MiB."""
    return measure_stage(sys.executable, *args)[1]


@pytest.mark.slow  # jobs measured (8 s; make test-slow)
def test_a_job_asks_for_the_memory_its_stage_uses(tmp_path):
    """Predeform, relax and aggregate of a 96 x 48 case on the torso, each its own process as
    a Snakemake job is: each peak is under what the job asks (measured 245-270 MiB against
    asks of 540-560 MB); a finer grid and a mesh body ask more."""
    material = tmp_path / "powernet.nc"
    peak_mib("material", "ingest", str(ROOT / "data/materials/powernet.csv"), "-o", str(material))
    case = {
        "material": str(material),
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.80, "top": 1.25, "reduction": 0.15, "grid": [96, 48]},
    }
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(case))
    initial, relaxed, result = (tmp_path / name for name in ("i.nc", "r.nc", "a.nc"))
    commands = {
        "predeform": ("predeform", str(path), "-o", str(initial)),
        "relax": ("relax", str(initial), "-o", str(relaxed)),
        "aggregate": ("aggregate", str(relaxed), "-o", str(result)),
    }
    for stage, command in commands.items():
        asked = stage_resources(stage, validate_case(case))
        assert peak_mib(*command) * 2**20 / 1e6 < asked.mem_mb, stage
        assert asked.runtime >= 1
        finer = validate_case({**case, "garment": {**case["garment"], "grid": [384, 192]}})
        assert stage_resources(stage, finer).mem_mb > asked.mem_mb
        on_mesh = validate_case({**case, "body": {"mesh": "scan.obj"}})
        assert stage_resources(stage, on_mesh).mem_mb > asked.mem_mb
    coarse = validate_case(case)
    assert stage_resources("relax", finer).runtime > stage_resources("relax", coarse).runtime
