"""A power-net tube cut 20 % small on a cylinder of radius 0.1 m: predeform, relax, aggregate,
and Laplace's law p = T / r on every interior row (docs/architecture.md walks it through the
wings; tests/test_examples.py runs it)."""

import numpy as np

from cloth.case.case import validate_case
from cloth.files.body import body_from_config
from cloth.files.material import load_fabric
from cloth.garment.predeform import predeform
from cloth.results.fields import node_fields
from cloth.solvers import Settings, relax

RADIUS = 0.1  # m
case = validate_case(
    {
        "material": "powernet",
        "body": {"cylinder": {"radius": RADIUS}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [96, 6]},
    }
)
body, record = body_from_config(case.body.block)  # the cylinder, and its record
state = predeform(case, load_fabric("powernet"), body, record)
final = relax(state, body, Settings(method="newton")).final
fields = node_fields(
    state.grid,
    final.x,
    final.springs,
    state.fabric.thickness,
    final.forces,
    final.unbalanced,
    final.on_body,
    final.normal,
    state.constraint,
)
pressure = fields.pressure.reshape(6, 96)[1:-1]  # Pa, interior rows
tension = fields.tension_weft.reshape(6, 96)[1:-1]  # N/m
np.testing.assert_allclose(pressure, tension / RADIUS, rtol=1e-3)  # Laplace: p = T / r
print(f"p = {pressure.mean():.1f} Pa = T / r = {tension.mean() / RADIUS:.1f} Pa")
