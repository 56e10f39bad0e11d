# cloth: stress and body pressure of stretch fabric worn on a body.
# This file is a table of contents: the rules live in workflow/rules/, one file per stage.
import os

from snakemake.utils import min_version, validate

min_version("9.0")

# the working directory's config/config.yaml, else the bundled default (any working directory);
# read only where no --configfile is given, so that another config is never merged over the
# default's keys (its bodies and designs would run too)
DEFAULT_CONFIG = "config/config.yaml"
if not os.path.exists(DEFAULT_CONFIG):
    DEFAULT_CONFIG = os.path.join(workflow.basedir, DEFAULT_CONFIG)
# the config this run reads (the first given): its name names the results folder
# (cloth/pipeline/layout.py)
CONFIG_FILE = (workflow.overwrite_configfiles or [DEFAULT_CONFIG])[0]

if not workflow.overwrite_configfiles:

    configfile: DEFAULT_CONFIG


validate(config, "workflow/schemas/config.schema.yaml")


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/materials.smk"
include: "workflow/rules/bodies.smk"
include: "workflow/rules/predeform.smk"
include: "workflow/rules/relax.smk"
include: "workflow/rules/aggregate.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/sweep.smk"
include: "workflow/rules/design.smk"
include: "workflow/rules/wearers.smk"
include: "workflow/rules/sizes.smk"
include: "workflow/rules/compare.smk"


rule all:
    default_target: True
    input:
        all_outputs(),
