"""The fabric: stress-strain curves and the lab tables they come from.

* `cloth.materials.curves`: piecewise-linear stress-strain curves and the `Fabric`;
* `cloth.materials.labcsv`: one lab table's columns, units and numbers;
* `cloth.materials.labtables`: cycles, branches and set strains of lab tables, into a `Material`;
* `cloth.materials.fitting`: monotone piecewise-linear fits of dense lab points.
"""
