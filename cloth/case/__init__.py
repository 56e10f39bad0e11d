"""The case, typed: `Case` and its blocks (`cloth.case.case`), the solver's `Settings`, and the
skin models' `Tissue`, `Contact` and `Skin`."""

from cloth.case.case import BODY_KINDS, BodySpec, Case, GarmentSpec, load_case, validate_case
from cloth.case.reading import Reading, Sensor
from cloth.case.settings import LINEAR_SOLVERS, METHODS, Settings
from cloth.case.skin import SLIP_FRACTION, Band, Contact, Skin, Tissue

__all__ = [
    "BODY_KINDS",
    "LINEAR_SOLVERS",
    "METHODS",
    "SLIP_FRACTION",
    "Band",
    "BodySpec",
    "Case",
    "Contact",
    "GarmentSpec",
    "Reading",
    "Sensor",
    "Settings",
    "Skin",
    "Tissue",
    "load_case",
    "validate_case",
]
