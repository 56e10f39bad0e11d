"""The workflow's file layout: where each file of a config's run goes, under its results folder
(the one place that knows; the rules name their files through a `Layout`).

Each config writes into its own folder, so that one run never overwrites another's sweep or
designs (`results_folder`): the config's ``results`` key where it gives one, else ``results``
for the default config (a file named ``config.yaml``) and ``results-<name>`` for a config file
``<name>.yaml`` (``config/stocking.yaml`` writes into ``results-stocking/``). Paths are relative
to the working directory unless the config gives an absolute one.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from cloth.errors import InputError
from cloth.paths import path_form

#: The default config's results folder, relative to the working directory.
RESULTS = "results"
#: The file name of the default config (its folder is `RESULTS`).
DEFAULT_CONFIG_NAME = "config.yaml"


def results_folder(config: dict, config_file: str | Path | None = None) -> str:
    """The folder a config writes into: its ``results`` key, else one named for the config
    file ``config_file`` (module docstring); `RESULTS` for no file or the default config."""
    if "results" in config:
        folder = str(path_form(config["results"], "config", "results")).rstrip("/")
        if folder in ("", "."):
            raise InputError(
                "give a folder for the results, not the working directory itself",
                "config",
                "results",
            )
        return folder
    if config_file is None or Path(config_file).name == DEFAULT_CONFIG_NAME:
        return RESULTS
    return f"{RESULTS}-{Path(config_file).stem}"


@dataclass(frozen=True)
class Layout:
    """The files of a run whose results folder is ``root``; each method's name argument
    defaults to the rules' wildcard pattern."""

    root: str = RESULTS

    def material_file(self, suffix: str, material: str = "{material}") -> str:
        """A material's file: ``nc`` (ingested curves) or ``png`` (its figure)."""
        return f"{self.root}/materials/{material}.{suffix}"

    def body_file(self, suffix: str, body: str = "{body}") -> str:
        """A body's file: ``ply`` (a torso's mesh), ``txt`` (its check), ``surface.nc`` (a
        mesh's fitted surface), ``check.txt``, ``curvature.png``."""
        return f"{self.root}/bodies/{body}.{suffix}"

    def case_file(self, name: str, case: str = "{case}") -> str:
        """A case's file: ``case.yaml``, ``initial.nc``, ``relaxed.nc``,
        ``result.nc``, ``summary.csv``, ``garment.html`` or ``figures`` (its figures)."""
        return f"{self.root}/cases/{case}/{name}"

    def sweep_file(self, name: str) -> str:
        """A file of the sweep and its design: ``sweep.nc``, ``sweep.csv``, ``design.png``,
        ``sweep_on_body.png``, ``design.csv``, ``design_confirmed.csv``."""
        return f"{self.root}/{name}"

    def design_file(self, name: str, design: str = "{design}") -> str:
        """A file of a profile design: ``start.yaml``, ``design_confirmed.csv``,
        ``design_profile.png``, ``pattern.csv``, ``pattern.svg``, ``case.yaml``,
        ``confirmed/``."""
        return f"{self.root}/designs/{design}/{name}"

    def wearers_file(self, name: str, entry: str = "{entry}") -> str:
        """A file of a wearers entry (`cloth.pipeline.wearers`): ``wearers.csv``,
        ``wearers.nc``, ``wearers.png``."""
        return f"{self.root}/wearers/{entry}/{name}"

    def size_chart_file(self, name: str, entry: str = "{entry}") -> str:
        """A file of a size chart entry (`cloth.pipeline.sizecharts`): ``start.yaml``,
        ``sizes.csv``, ``chart.csv``, ``fabric_requirement.csv``, ``sizes.png``."""
        return f"{self.root}/size_charts/{entry}/{name}"


#: The default config's layout.
DEFAULT = Layout()
