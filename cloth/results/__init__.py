"""Pure computations on a relaxed garment: fields, pressure, landmarks.

* `cloth.results.fields`: node and spring stresses, strains, tensions and pressure;
* `cloth.results.pressure`: reactions, pressure units, compression classes;
* `cloth.results.landmarks`: the girth lines and their summaries;
* `cloth.results.richardson`: how far a reported value is from the converged garment;
* `cloth.results.resolution`: where a mesh body's own resolution limits a girth line.
"""
