"""Generate ``example_cone.csv``: SYNTHETIC pressure-sensor readings, made by cloth.

Not a measurement. The known case ``cone.yaml`` (friction 0.3, tissue modulus 20 kPa) is run,
the model's 50 mm probe is read at the places of ``places.csv`` (`cloth.stages.compare.
synthetic`), each twice, and Gaussian noise of 1.5 mmHg (fixed seed) is added: what a sensor
would read on that case. ``cloth calibrate cone_start.yaml example_cone.csv`` should find the
case's friction and modulus within its intervals (docs/validation.md, "Your own measurements").
Run it to regenerate the file (fixed seed; the equilibrium to the solver's tolerance):

    python data/measurements/generate_example.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from cloth.files.measured import read_measurements, write_measurements
from cloth.io import read_netcdf
from cloth.results.pressure import MMHG
from cloth.stages.case import run_case
from cloth.stages.compare import RESULT_VARIABLES, synthetic

HERE = Path(__file__).resolve().parent
NOISE_MMHG = 1.5
REPEATS = 2
SEED = 20261206
HEADER = (
    "SYNTHETIC readings made by cloth, not a measurement (data/measurements/README.md):\n"
    "the model's 50 mm probe on cone.yaml (friction 0.3, tissue modulus 20 kPa) at the places\n"
    f"of places.csv, {REPEATS} repeats each, plus Gaussian noise of {NOISE_MMHG} mmHg "
    f"(seed {SEED}); by generate_example.py"
)


def generate(output: Path, folder: Path) -> Path:
    """Run cone.yaml in ``folder`` and write the readings to ``output``."""
    run_case(HERE / "cone.yaml", folder, {}, stop_after="aggregate")
    result = read_netcdf(folder / "result.nc", "result", RESULT_VARIABLES)
    readings = synthetic(
        result, read_measurements(HERE / "places.csv"), NOISE_MMHG * MMHG, SEED, REPEATS
    )
    return write_measurements(readings, output, HEADER)


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as scratch:
        print(generate(HERE / "example_cone.csv", Path(scratch)))
