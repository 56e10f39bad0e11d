"""Rigid bodies the fabric is worn on (metres, z up), one module a concept:

* `cloth.bodies.base`: the `Body` protocol, cross-section polygons, the analytic base;
* `cloth.bodies.analytic`: cylinder, elliptic cylinder and cone in closed form (validation);
* `cloth.bodies.mesh`: triangle meshes (load, units and axes, checks, repair);
* `cloth.bodies.sections`: a mesh's cross-sections (loops, closure, which loop to wrap);
* `cloth.bodies.implicit`: closest points and curvature of a smooth implicit surface;
* `cloth.bodies.torso`: the parametric torso from a size chart, its mesh and smooth surface;
* `cloth.bodies.spline`: the cubic B-spline field the fitted surfaces are made of;
* `cloth.bodies.surface`: the smooth surface fitted to any mesh (the default contact surface
  of a mesh body); `cloth.bodies.smoothmesh`: the mesh body contacted through it;
  `cloth.bodies.surfacefile`: its file and cache;
* `cloth.bodies.drawing`: a result's body as triangles for figures;
* `cloth.bodies.check`: `cloth body check`;
* `cloth.bodies.factory`: the body of a case's ``body`` block.
"""

from cloth.bodies.analytic import Cone, Cylinder, EllipticCylinder
from cloth.bodies.base import Body, hull_polygon, polygon_perimeter
from cloth.bodies.factory import body_from_config, body_from_record
from cloth.bodies.mesh import MeshBody
from cloth.bodies.sections import loop_around

__all__ = [
    "Body",
    "Cone",
    "Cylinder",
    "EllipticCylinder",
    "MeshBody",
    "body_from_config",
    "body_from_record",
    "hull_polygon",
    "loop_around",
    "polygon_perimeter",
]
