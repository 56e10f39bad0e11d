"""The garment: its spring grid, mechanics, state, and the pattern wrapped on the body.

* `cloth.garment.grid`: node numbering, kinds, springs, rest lengths and areas, node areas;
* `cloth.garment.mechanics`: energy, forces and stiffness over the springs;
* `cloth.garment.state`: the `State` every stage hands on (grid, positions, case, body record);
* `cloth.garment.predeform`: the pattern cut small and wrapped on the body;
* `cloth.garment.worn`: the worn garment's rest lengths (the fabric's set strain).
"""
