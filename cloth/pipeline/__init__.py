"""The pipeline around the stages: cases, plans, sweeps, and what jobs ask for.

* `cloth.pipeline.plan`: every case of a pipeline config, by name, and the file layout;
* `cloth.pipeline.variants`: the sweep's skin and wear variants;
* `cloth.pipeline.sweep`: sweeps and the design answer;
* `cloth.pipeline.guard`: memory and time estimated before work;
* `cloth.pipeline.resources`: what a case's jobs ask a cluster for.
"""
