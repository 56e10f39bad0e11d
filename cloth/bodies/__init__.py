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
* `cloth.bodies.proximity`: exact closest points and signed distances on a triangle mesh.

A body is built from a case's ``body`` block by `cloth.files.body` (it reads the mesh, chart or
fitted-surface files), drawn by `cloth.figures.drawing`, checked by `cloth.stages.bodycheck`.
"""

from cloth.bodies.analytic import Cone, Cylinder, EllipticCylinder
from cloth.bodies.base import Body, hull_polygon, polygon_perimeter
from cloth.bodies.mesh import MeshBody
from cloth.bodies.sections import loop_around

__all__ = [
    "Body",
    "Cone",
    "Cylinder",
    "EllipticCylinder",
    "MeshBody",
    "hull_polygon",
    "loop_around",
    "polygon_perimeter",
]
