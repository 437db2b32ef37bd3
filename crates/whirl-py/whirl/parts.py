"""A model built in code from parts: one object per table of the model file.

    from whirl import Bearing, Disk, Material, Model, Shaft, Unbalance

    model = Model.build("rotor", [
        Material(name="steel", young_modulus=2.11e11, density=7810),
        Shaft(length="1.3 m", outer_diameter="55.9 mm", material="steel", elements=20),
        Disk(node=10, mass="10 kg", polar_inertia=0.05, diametral_inertia=0.025),
        [Bearing(node=n, kxx=1e8, kyy=1e8) for n in (0, 20)],
        Unbalance(node=10, eccentricity="40 um"),
    ])

A part's keywords are the keys of its table in the model file (docs/model-file.md), its
values what the file takes: numbers in SI, text with a unit (``"20 um"``) or pint
quantities. The library checks them when the model is built, as it checks a model file,
and an unknown or wrong key is named (``shaft[0].lenght``). ``model.parts()`` gives a
model's parts back, so ``Model.build(model.name, model.parts(), model.gravity)`` is the
same model, and ``part.to_dict()`` is the part's table.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, ClassVar

from ._quantity import plain


class Part:
    """One table of the model file; subclasses name which (:attr:`table`)."""

    #: The model file's name of the table: ``shaft`` for ``[[shaft]]``.
    table: ClassVar[str]
    #: Whether the file holds a list of these (``[[shaft]]``) or one (``[damping]``).
    repeated: ClassVar[bool] = True

    __slots__ = ("fields",)

    def __init__(self, **fields: Any):
        #: The table's keys and values, as given.
        self.fields = fields

    def to_dict(self) -> dict[str, Any]:
        """The part's table as the model file writes it (pint quantities as text with a
        unit, parts inside it as their tables)."""
        return plain(self.fields)

    def __getattr__(self, key: str) -> Any:
        if key.startswith("__") or key == "fields":
            # Asked before `fields` is set (unpickling, copying): not a key of the table.
            raise AttributeError(key)
        try:
            return self.fields[key]
        except KeyError:
            raise AttributeError(
                f"{type(self).__name__} has no `{key}`: it has {', '.join(self.fields) or 'no keys'}"
            ) from None

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.fields.items())
        return f"{type(self).__name__}({args})"

    def __getstate__(self) -> dict[str, Any]:
        return self.fields

    def __setstate__(self, fields: dict[str, Any]) -> None:
        self.fields = fields


class Material(Part):
    """``[[material]]``: a material referred to by name (``young_modulus``, ``density``, ...)."""

    table = "material"


class Shaft(Part):
    """``[[shaft]]``: a shaft section, in order from z = 0 (``length``, ``outer_diameter``,
    ``material``, ``elements``, ...)."""

    table = "shaft"


class Elements(Part):
    """``[elements]``: options for every beam element (``rotary_inertia``, ``gyroscopic``, ...)."""

    table = "elements"
    repeated = False


class Disk(Part):
    """``[[disk]]``: a rigid disk (``node``, ``mass``, ``polar_inertia``, ``diametral_inertia``)."""

    table = "disk"


class Bearing(Part):
    """``[[bearing]]``: a linear support (``node``, ``kxx``, ``kyy``, ``cxx``, ...)."""

    table = "bearing"


class RollerBearing(Part):
    """``[[roller_bearing]]``: a cylindrical roller bearing with clearance (``node``,
    ``rollers``, ``clearance``, ...; ``waviness`` and ``defect`` lists of :class:`Waviness`
    and :class:`Defect`)."""

    table = "roller_bearing"


class BallBearing(Part):
    """``[[ball_bearing]]``: a deep-groove or angular-contact ball bearing."""

    table = "ball_bearing"


class Housing(Part):
    """``[[housing]]``: a bearing housing, pedestal or casing (``squeeze_film`` a
    :class:`SqueezeFilm`)."""

    table = "housing"


class Damping(Part):
    """``[damping]``: Rayleigh damping of the rotor (``alpha``, ``beta``)."""

    table = "damping"
    repeated = False


class Unbalance(Part):
    """``[[unbalance]]``: an unbalance (``node``, ``mass`` and ``eccentricity``, ``phase``)."""

    table = "unbalance"


class Operating(Part):
    """``[operating]``: the operating speed range (``min_speed``, ``max_speed``)."""

    table = "operating"
    repeated = False


class Waviness(Part):
    """``[[roller_bearing.waviness]]``: a ring's waviness, inside :class:`RollerBearing`."""

    table = "roller_bearing.waviness"


class Defect(Part):
    """``[[roller_bearing.defect]]``: a localised defect, inside :class:`RollerBearing`."""

    table = "roller_bearing.defect"


class SqueezeFilm(Part):
    """``[housing.squeeze_film]``: a squeeze-film damper, inside :class:`Housing`."""

    table = "housing.squeeze_film"
    repeated = False


#: The model file's top-level tables, in the order a model file writes them.
TOP_LEVEL: tuple[type[Part], ...] = (
    Material,
    Shaft,
    Elements,
    Disk,
    Bearing,
    RollerBearing,
    BallBearing,
    Housing,
    Damping,
    Unbalance,
    Operating,
)
#: The tables inside other tables: (owner, key) -> part.
_NESTED: dict[tuple[str, str], type[Part]] = {
    tuple(p.table.split(".")): p for p in (Waviness, Defect, SqueezeFilm)  # type: ignore[misc]
}
_BY_TABLE = {p.table: p for p in TOP_LEVEL}


def tables_of(parts: Iterable[Any]) -> dict[str, Any]:
    """The model file's tables of ``parts`` (nested lists flattened): a list for each
    repeated table, in the order given, and the table itself for the others."""
    tables: dict[str, Any] = {}
    for part in _flat(parts):
        if not isinstance(part, Part):
            raise TypeError(
                f"expected a whirl part (Shaft, Disk, Bearing, ...), not {type(part).__name__}"
            )
        if part.table not in _BY_TABLE:
            owner, key = part.table.split(".")
            raise TypeError(
                f"a {type(part).__name__} sits inside its {owner} table: give it as "
                f"`{key}` of {_BY_TABLE[owner].__name__}, not on its own"
            )
        if part.repeated:
            tables.setdefault(part.table, []).append(part.to_dict())
        elif part.table in tables:
            raise ValueError(f"a model has one [{part.table}] table, and two were given")
        else:
            tables[part.table] = part.to_dict()
    return tables


def parts_of(tables: Mapping[str, Any]) -> list[Part]:
    """The parts of a model file's tables, in the model file's order of tables (the
    top-level keys ``name`` and ``gravity`` are not parts)."""
    parts: list[Part] = []
    for part in TOP_LEVEL:
        value = tables.get(part.table)
        if value is None:
            continue
        for table in value if part.repeated else [value]:
            parts.append(part(**_nested_parts(part.table, table)))
    return parts


def _nested_parts(owner: str, table: Mapping[str, Any]) -> dict[str, Any]:
    fields = dict(table)
    for (outer, key), part in _NESTED.items():
        if outer != owner or key not in fields:
            continue
        value = fields[key]
        fields[key] = [part(**v) for v in value] if part.repeated else part(**value)
    return fields


def _flat(parts: Iterable[Any]) -> Iterable[Any]:
    for part in parts:
        if isinstance(part, (list, tuple)):
            yield from _flat(part)
        else:
            yield part
