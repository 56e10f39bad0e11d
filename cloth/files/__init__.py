"""The project's files: one reader and one writer per format.

* `cloth.files.material`: ``material.nc``;
* `cloth.files.state`: ``initial.nc`` and the state part of ``relaxed.nc``;
* `cloth.files.relaxed`: ``relaxed.nc``'s history and solver attributes;
* `cloth.files.result`: ``result.nc`` and ``summary.csv``;
* `cloth.files.skin`: the skin models' variables in relaxed.nc and result.nc;
* `cloth.files.surface`: ``surface.nc`` (a mesh body's fitted surface) and its cache;
* `cloth.files.body`: the body a case's block or a file's record names, rebuilt from its files.
"""
