"""The pipeline's stages, one function each, files in and files out; the CLI (`cloth.cli`)
only parses arguments and calls them, and each Snakemake rule runs one through the CLI.

=================  ====================================  ==========================================
stage              function                              files
=================  ====================================  ==========================================
ingest             `inputs.ingest_material`              lab tables -> material.nc (+ figure)
body               `inputs.torso_file`                   size chart -> torso mesh
predeform          `case.predeform_file`                 case.yaml -> initial.nc (+ figure)
relax              `case.relax_file`                     initial.nc -> relaxed.nc
aggregate          `results.write_result`                relaxed.nc -> result.nc, summary.csv
figures            `results.figures`                     result.nc -> figures/*.png
view               `results.view`                        result.nc -> garment.html
run                `case.run_case`                       case.yaml -> all of the above, one folder
sweep              `sweep.sweep_files`                   results -> sweep.nc, sweep.csv, figures
design, confirm    `sweep.design_file`, `confirm_file`   sweep.nc -> design.csv -> confirmed.csv
=================  ====================================  ==========================================

The body stages `cloth body check` and `cloth body fit` are `cloth.stages.bodycheck.describe` and
`cloth.files.surface.load_or_fit`.

Import a stage from its module: this package imports none of them, so that a rule's process
imports what its one stage needs (predeform no drawing; issue 54's overhead).
"""
