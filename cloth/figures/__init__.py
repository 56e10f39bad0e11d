"""Everything drawn from a result (matplotlib on Agg; plotly for the view).

* `cloth.figures.plots`: flat maps, curves, convergence, design plots;
* `cloth.figures.onbody`: the garment on the body from three sides;
* `cloth.figures.view`: the interactive HTML view;
* `cloth.figures.export`: PLY, VTU and CSV export;
* `cloth.figures.drawing`: the body a result records, as triangles to draw;
* `cloth.figures.ranges`: the colour ranges a sweep's figures share, read once for it.
"""
