"""A validation study: one garment compared on several subjects (``cloth compare STUDY.yaml``).

Published validations of compression garments are laid out this way: one stocking, many legs,
each leg's readings at named points. A study file (YAML):

.. code-block:: yaml

    case: stocking.yaml         # the garment: a case whose garment.pattern fixes the pattern
    subjects:
      - name: anna
        body: {mesh: scans/anna.ply, units: mm, kind: leg}   # any body block of a case
        measurements: readings/anna.csv                      # her readings (docs/outputs.md)
      - name: bea
        body: {avatar: {chart: bea_chart.csv, size: bea}}    # her girths as a one-row chart
        measurements: readings/bea.csv

Relative paths resolve against the study file's folder (the case's own, against the case's).
Each subject's case is the study's case with her body (``{output}/{name}/case.yaml``), run
to its result.nc; her readings (their ``subject`` column, where present, is replaced by her
name) are compared with it (`cloth.stages.compare.compare_result`), and the rows of every
subject are pooled into one compare.csv, agreement.csv (a row per subject and ``all``),
compare.nc and compare.png. The case must wear a pattern (``garment.pattern``: cut for a body,
or a pattern.csv): a garment cut on each wearer would be a different garment on each.
"""

from __future__ import annotations

import logging
import re
from dataclasses import replace
from pathlib import Path

import yaml

from cloth.case.case import load_case, validate_case
from cloth.case.locations import relocated
from cloth.errors import InputError
from cloth.files.casefile import write_case
from cloth.files.measured import read_measurements
from cloth.io import atomic_folder, read_netcdf, resolve
from cloth.results.agreement import Compared
from cloth.stages.case import run_case
from cloth.stages.compare import RESULT_VARIABLES, compare_result, write_compared

log = logging.getLogger(__name__)

#: A subject's name: it names a folder.
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
#: A subject's keys.
SUBJECT_KEYS = ("name", "body", "measurements")


def read_study(path: Path) -> tuple[dict, list[dict]]:
    """The study file at ``path`` (module docstring): its case mapping (paths relative to the
    study's folder) and subjects (``measurements`` resolved); `InputError` in one line naming
    the file and the key."""
    if not path.is_file():
        raise InputError("study file not found; check the path", path)
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise InputError(f"not valid YAML ({getattr(exc, 'problem', exc)})", path) from None
    if not isinstance(data, dict) or set(data) - {"case", "subjects"}:
        raise InputError("a study has the keys case and subjects (docs/validation.md)", path)
    if "case" not in data:
        raise InputError("missing key: the case whose garment every subject wears", path, "case")
    case_path = resolve(str(data["case"]), path.parent)
    case = load_case(case_path)
    if case.garment.pattern is None:
        raise InputError(
            "the case's garment is cut on each wearer, so each subject would wear another "
            "garment; give garment.pattern (cut for a body, or a pattern.csv)",
            path,
            "case",
        )
    subjects = data.get("subjects")
    if not isinstance(subjects, list) or not subjects:
        raise InputError("give a list of subjects, each a name, body and measurements", path)
    names = set()
    for k, subject in enumerate(subjects):
        where = f"subjects[{k}]"
        if not isinstance(subject, dict) or sorted(subject) != sorted(SUBJECT_KEYS):
            raise InputError(
                f"a subject has exactly the keys {', '.join(SUBJECT_KEYS)}", path, where
            )
        name = str(subject["name"])
        if not NAME.match(name) or name in names:
            raise InputError(
                f"name {name!r} must be unique, of letters, digits, _ . -", path, f"{where}.name"
            )
        names.add(name)
        subject["measurements"] = resolve(str(subject["measurements"]), path.parent)
    return relocated(case.to_dict(), case_path.parent, path.parent), subjects


def run_study(path: Path, output: Path, overrides: dict) -> dict[str, Path]:
    """Run and compare every subject of the study at ``path`` into ``output`` (module
    docstring); the pooled outputs' paths, by name."""
    case, subjects = read_study(path)
    checked = []  # every subject's readings and case checked before anything runs
    for k, subject in enumerate(subjects):
        measured = read_measurements(subject["measurements"])
        measured = replace(measured, subject=(subject["name"],) * len(measured))
        data = {**case, "body": subject["body"]}
        validate_case(data, f"{path}: subjects[{k}]")
        checked.append((subject["name"], measured, data))
    sources = {"study": path}
    with atomic_folder(output) as folder:  # whole or absent, whichever subject fails
        parts: list[Compared] = []
        for k, (name, measured, data) in enumerate(checked):
            case_file = write_case(data, folder / name / "case.yaml", path.parent)
            log.info("study: subject %s (%d of %d)", name, k + 1, len(checked))
            try:
                run_case(case_file, folder / name, overrides, stop_after="aggregate")
            except InputError as exc:  # her body's files: named by the study's key
                raise InputError(exc.detail, f"{path}: subjects[{k}].body", exc.field) from None
            result = read_netcdf(folder / name / "result.nc", "result", RESULT_VARIABLES)
            parts.append(compare_result(result, measured))
        paths = write_compared(Compared.joined(parts), folder, sources, output)
    return {key: output / value.relative_to(folder) for key, value in paths.items()}
