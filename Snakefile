# cloth: stress and body pressure of stretch fabric worn on a body.
# The workflow is workflow/Snakefile, a table of contents of its rules; the installed package
# runs the same file (`cloth pipeline`), so this one includes it and names its default target
# (an included file's default target is not the run's: Snakemake keeps the main file's).


include: "workflow/Snakefile"


rule default:
    default_target: True
    input:
        rules.all.input,
