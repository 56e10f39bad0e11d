"""The case, typed: one simulation's fabric, body, garment, skin and solver, frozen.

`Case.from_dict` builds it from a case mapping that `cloth.case.case.validate_case`
checked against the schema and filled with defaults (or one read back from a state file, which
was). Each block is its own type, read by attribute, never by string key:

=============  ==========================================  ===================================
case key       type                                        read by
=============  ==========================================  ===================================
material       str (a lab table, a material.nc or a name)  `cloth.files.material.load_fabric`
fabric_scale   float, 1: the fabric's stresses scaled      `cloth.files.material.case_fabric`
body           `BodySpec` (kind, its block, `Tissue`)      `cloth.files.body.body_from_config`
garment        `GarmentSpec`                               `cloth.garment.predeform`
contact        `Contact` (friction, slip length)           `Case.skin`
landmarks      name -> height, m                           `cloth.stages.results`
girth_reading  `Reading` (band, probe; with ``sensors``)   `cloth.results.bands`
judge          `Judge` (classes, graduation, bands)        `cloth.results.judging`
solver         `Settings`                                  `cloth.solvers.relax`
=============  ==========================================  ===================================

The skin models a garment meets (`Skin`: the tissue layer and the friction) are the state's,
copied from the case by predeform, so the solvers take `Settings` and the skin, never the case.

The constructors check what a type knows (a positive tissue modulus, bands inside the garment,
a friction coefficient >= 0, a solver that can solve the skin models) and raise `InputError`
naming the field; `Case.from_dict` adds the case's name. `Case.to_dict` gives back the mapping
it was built from (state files and ``cloth case write`` store it as JSON and YAML).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from cloth.case.judge import Judge
from cloth.case.pieces import Pieces
from cloth.case.profile import Profile
from cloth.case.reading import Reading
from cloth.case.settings import Settings
from cloth.case.skin import Contact, Skin, Tissue
from cloth.case.validate import BODY_KINDS, checked_mapping, read_mapping
from cloth.errors import InputError


@dataclass(frozen=True)
class BodySpec:
    """The case's ``body`` block: its ``kind`` (one of `BODY_KINDS`), the block itself (a copy
    each time it is read: `cloth.files.body.body_from_config` takes it) and its tissue."""

    kind: str
    _block: Mapping[str, Any] = field(repr=False)
    tissue: Tissue | None = None

    @property
    def block(self) -> dict[str, Any]:
        return copy.deepcopy(dict(self._block))

    def option(self, key: str, default: Any = None) -> Any:
        """A key of the block (a mesh body's ``units``, ``surface``, ...) or ``default``."""
        return copy.deepcopy(self._block.get(key, default))

    @property
    def params(self) -> dict[str, Any]:
        """The parameters of a parametric body (``torso``, ``cylinder``, ...): its sub-block;
        empty for a mesh."""
        return copy.deepcopy(dict(self._block.get(self.kind, {}))) if self.kind != "mesh" else {}


@dataclass(frozen=True)
class GarmentSpec:
    """The case's ``garment`` block (docs/config.md): heights m, moduli Pa, strains 1."""

    bottom: float
    top: float
    grid: tuple[int, int]
    reduction: float | Mapping[str, float] | None = None
    circumference: float | None = None
    lengthwise_reduction: float | Mapping[str, float] = 0.0
    edges: str = "sliding"
    around: str = "weft"
    offset: float = 1e-4
    loop_point: tuple[float, float] | None = None
    shear_modulus: float | None = None
    bend_modulus: float | None = None
    worn: bool = False
    set_strain: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    error_estimate: bool = True
    #: Rows graded toward both edges by this (`cloth.garment.rows`; 0: equally spaced).
    row_grading: float = 0.0
    #: n and m divided by this from each error-estimate level to the next (`cloth.stages.levels`).
    level_ratio: float = 2.0
    #: ``pattern``: the block (`cloth.garment.cut`): ``body`` or ``file``, and ``place``.
    pattern: Mapping[str, Any] | None = None

    #: With ``grid: auto`` (`auto` True; ``grid`` is then (0, 0) until predeform chooses the
    #: start): the relative error to refine to, and the largest grid (nodes).
    auto: bool = False
    accuracy: float = 0.01
    max_nodes: int = 100_000
    #: Bands, panels, layers and seams (`cloth.case.pieces`); none: one fabric.
    pieces: Pieces = field(default_factory=Pieces)

    @property
    def nodes(self) -> int:
        """The grid's nodes; with ``grid: auto``, the most it may have (`max_nodes`)."""
        return self.max_nodes if self.auto else self.grid[0] * self.grid[1]

    @property
    def place(self) -> str | None:
        """The girth line a pattern is placed by (`cloth.garment.cut.placement`), if given."""
        return None if self.pattern is None else self.pattern.get("place")

    @property
    def reduction_profile(self) -> Profile | None:
        """The graded pattern's reduction (`cloth.case.profile`); None for a rectangle."""
        return None if self.reduction is None else Profile.of(self.reduction)

    @property
    def lengthwise_profile(self) -> Profile:
        """The warp's reduction (`cloth.case.profile`)."""
        return Profile.of(self.lengthwise_reduction)

    @property
    def moduli(self) -> dict[str, float]:
        """The optional linear springs' moduli (Pa), by key, where given."""
        given = {"shear_modulus": self.shear_modulus, "bend_modulus": self.bend_modulus}
        return {key: float(value) for key, value in given.items() if value is not None}

    @classmethod
    def from_block(cls, block: Mapping[str, Any]) -> GarmentSpec:
        loop = block.get("loop_point")
        auto = block["grid"] == "auto"
        return cls(
            bottom=float(block["bottom"]),
            top=float(block["top"]),
            grid=(0, 0) if auto else (int(block["grid"][0]), int(block["grid"][1])),
            reduction=_frozen(block.get("reduction")),
            circumference=block.get("circumference"),
            lengthwise_reduction=_frozen(block.get("lengthwise_reduction", 0.0)),
            edges=block.get("edges", "sliding"),
            around=block.get("around", "weft"),
            offset=float(block.get("offset", 1e-4)),
            loop_point=None if loop is None else (float(loop[0]), float(loop[1])),
            shear_modulus=block.get("shear_modulus"),
            bend_modulus=block.get("bend_modulus"),
            worn=bool(block.get("worn", False)),
            set_strain=MappingProxyType(dict(block.get("set_strain") or {})),
            error_estimate=bool(block.get("error_estimate", True)),
            level_ratio=float(block.get("level_ratio", 2.0)),
            row_grading=float(block.get("row_grading", 0.0)),
            pattern=None if block.get("pattern") is None else MappingProxyType(block["pattern"]),
            auto=auto,
            accuracy=float(block.get("accuracy", 0.01)),
            max_nodes=int(block.get("max_nodes", 100_000)),
            pieces=Pieces.from_block(block),
        )


@dataclass(frozen=True, eq=False)
class Case:
    """One simulation, typed (module docstring). Equal when built from equal mappings."""

    material: str
    body: BodySpec
    garment: GarmentSpec
    contact: Contact
    solver: Settings
    landmarks: Mapping[str, float]
    _data: Mapping[str, Any] = field(repr=False)
    judge: Judge = field(default_factory=Judge)
    reading: Reading = field(default_factory=Reading)
    fabric_scale: float = 1.0

    @property
    def skin(self) -> Skin:
        """The skin models the case asks for: its body's tissue and its contact."""
        return Skin(self.body.tissue, self.contact, self.garment.pieces.grip)

    def to_dict(self) -> dict[str, Any]:
        """The mapping the case was built from (validated, defaults filled), a fresh copy."""
        return copy.deepcopy(dict(self._data))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Case) and self._data == other._data

    @classmethod
    def load(cls, path: str | Path) -> Case:
        """The case in the YAML file ``path``, validated as the command validates it (the
        schema, its defaults, every block's checks); `InputError` naming the file and the key.
        Its relative paths are relative to the file's folder where a stage reads them.

        Examples
        --------
        >>> import cloth
        >>> case = cloth.Case.load("case.yaml")  # doctest: +SKIP
        """
        return load_case(path)

    @classmethod
    def of(cls, data: Mapping[str, Any], source: str = "case") -> Case:
        """The case of the mapping ``data`` (as a case file holds it), validated as the
        command validates it; `InputError` naming ``source`` and the key.

        Examples
        --------
        >>> import cloth
        >>> case = cloth.Case.of(
        ...     {"material": "powernet", "body": {"torso": {"size": "M"}},
        ...      "garment": {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [24, 8]}}
        ... )
        >>> case.garment.grid
        (24, 8)
        """
        return validate_case(copy.deepcopy(dict(data)), source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "case") -> Case:
        """The typed case of a validated mapping (`cloth.case.case.validate_case`);
        `InputError` naming ``source`` and the field where a block does not hold."""
        data = copy.deepcopy(dict(data))
        try:
            return cls._build(data)
        except InputError as exc:
            raise InputError(exc.detail, source, exc.field) from None

    @classmethod
    def _build(cls, data: dict[str, Any]) -> Case:
        body_block = data["body"]
        kinds = [kind for kind in BODY_KINDS if kind in body_block]
        garment = GarmentSpec.from_block(data["garment"])
        tissue_block = body_block.get("tissue")
        tissue = None
        if tissue_block is not None:
            tissue = Tissue.from_block(tissue_block, garment.bottom, garment.top)
        contact_block = data.get("contact") or {}
        contact = Contact(contact_block.get("friction", 0.0), contact_block.get("slip_length"))
        block = data["solver"] = dict(data.get("solver") or {})
        # the fast path by default where it is one answer: Newton without friction (with the
        # tension field the energy is convex, so continuation ends where plain Newton does;
        # docs/validation.md, "Path agreement"); friction follows the path from the wrap
        grip = garment.pieces.grip  # a band's own friction (a gripper) is friction too
        fast = block.get("method", "newton") == "newton" and not contact.friction and not grip
        block.setdefault("continuation", fast)
        block.setdefault("reuse", fast)
        solver = _settings(block)
        Skin(tissue, contact, grip).check_solver(solver.method, solver.continuation)
        garment.pieces.check(garment.bottom, garment.top, list(data.get("landmarks") or {}))
        return cls(
            material=str(data["material"]),
            body=BodySpec(kinds[0] if kinds else "", MappingProxyType(body_block), tissue),
            garment=garment,
            contact=contact,
            solver=solver,
            landmarks=MappingProxyType(
                {str(k): float(v) for k, v in (data.get("landmarks") or {}).items()}
            ),
            _data=MappingProxyType(data),
            judge=Judge.from_block(data.get("judge")),
            reading=Reading.from_blocks(data.get("girth_reading"), data.get("sensors")),
            fabric_scale=float(data.get("fabric_scale", 1.0)),
        )


def validate_case(case: Case | dict[str, Any], source: str | Path = "case") -> Case:
    """The typed case of a case mapping: checked against the schema, its defaults filled
    (`cloth.case.validate.checked_mapping`), then built (`Case.from_dict`, which checks what
    each block's type knows). A `Case` is returned as it is: it was validated where it entered
    the process (the plan, a case file, a command's JSON, a state file), and functions handed
    one do not validate it again.

    Raises `InputError` naming ``source`` and the key path of the first problem.
    """
    if isinstance(case, Case):
        return case
    return Case.from_dict(checked_mapping(case, source), str(source))


def load_case(path: str | Path) -> Case:
    """Read and validate a YAML case file (`validate_case`)."""
    return Case.from_dict(read_mapping(path), str(path))


#: Solver keys whose defaults follow the case's skin (`Case._build`): Newton without friction
#: takes the fast path, friction the path from the wrap.
SKIN_DEFAULTS = ("continuation", "reuse")


def following_skin(data: Mapping[str, Any]) -> dict[str, Any]:
    """A copy of the case mapping ``data`` without its solver's `SKIN_DEFAULTS`, so that they
    take the defaults of the skin it has now (a validated case carries the old skin's)."""
    out = copy.deepcopy(dict(data))
    out["solver"] = {k: v for k, v in (out.get("solver") or {}).items() if k not in SKIN_DEFAULTS}
    return out


def _frozen(value: Any) -> Any:
    """A profile's mapping, read-only with text keys; a number as a float; None as None."""
    if isinstance(value, Mapping):
        return MappingProxyType({str(k): float(v) for k, v in value.items()})
    return None if value is None else float(value)


def _settings(block: Mapping[str, Any]) -> Settings:
    try:
        return Settings(**block)
    except InputError as exc:
        raise InputError(exc.detail, field=f"solver.{exc.field}") from None
