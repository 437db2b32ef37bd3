"""The rotor model: read from a model file, TOML text or a dict, edited by parameter paths."""

from __future__ import annotations

import json
import math
import os
import tomllib
import warnings
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from . import _whirl
from ._quantity import plain
from ._toml import located, model_text
from .parts import Part, parts_of, tables_of


class WhirlWarning(UserWarning):
    """A valid but implausible value in a model (the command line prints these on stderr)."""


class Model:
    """A validated rotor model.

    Build it with :meth:`from_file`, :meth:`from_toml` or :meth:`from_dict`; every way goes
    through the same validation as the command line, and a wrong value raises
    :class:`whirl.InputError` naming the file, line, column and field. Values are in the
    model file's units on the way in and SI inside.
    """

    __slots__ = ("_raw",)

    def __init__(self, raw: _whirl.Model):
        self._raw = raw

    @classmethod
    def _checked(cls, raw: _whirl.Model) -> Model:
        where = f"{raw.file}: " if raw.file is not None else ""
        for warning in raw.warnings():
            warnings.warn(f"{where}{warning}", WhirlWarning, stacklevel=3)
        return cls(raw)

    @classmethod
    def from_file(cls, path: str | os.PathLike[str]) -> Model:
        """Reads and validates a model file (TOML), e.g. ``examples/reference_rotor.toml``."""
        return cls._checked(_whirl.Model.from_file(os.fspath(path)))

    @classmethod
    def from_toml(cls, text: str, file: str | os.PathLike[str] | None = None) -> Model:
        """Validates a model given as TOML text; ``file`` names it in error messages."""
        return cls._checked(
            _whirl.Model.from_toml(text, None if file is None else os.fspath(file))
        )

    @classmethod
    def from_dict(cls, tables: Mapping[str, Any]) -> Model:
        """Validates a model given as a dict with the model file's tables and keys, e.g.
        ``{"name": "rotor", "shaft": [...], "disk": [...], "bearing": [...]}``; quantities
        may be numbers (SI), text with a unit (``"20 um"``) or pint quantities.
        ``Model.from_dict(model.to_tables())`` is the same model."""
        converted = plain(tables)
        bad = _unwritable(converted, "")
        if bad is not None:
            path, value = bad
            raise _whirl.InputError(
                f"`{path}`: {value!r} has no place in a model file (TOML has no NaN or "
                "infinity)\n  help: give a finite number or text with a unit"
            )
        text, paths = model_text(converted)
        try:
            raw = _whirl.Model.from_toml(text, None)
        except _whirl.InputError as e:
            # Located in text the caller never saw: named by the key instead.
            raise _whirl.InputError(located(str(e), paths)) from None
        return cls._checked(raw)

    @classmethod
    def build(
        cls, name: str, parts: Iterable[Part | Iterable[Part]], gravity: Any = None
    ) -> Model:
        """Validates a model built from parts (:mod:`whirl.parts`: :class:`~whirl.Shaft`,
        :class:`~whirl.Disk`, :class:`~whirl.Bearing`, :class:`~whirl.RollerBearing`,
        :class:`~whirl.Unbalance`, ...), given in any order and as lists or single parts;
        ``gravity`` along -y in m/s^2 (the model file's default when None).
        ``Model.build(model.name, model.parts(), model.gravity)`` is the same model."""
        tables: dict[str, Any] = {"name": name}
        if gravity is not None:
            tables["gravity"] = gravity
        return cls.from_dict({**tables, **tables_of(parts)})

    def parts(self) -> list[Part]:
        """The model's parts (:mod:`whirl.parts`), in the model file's order of tables,
        each holding its table's keys as the file writes them."""
        return parts_of(self.to_tables())

    def with_values(self, values: Mapping[str, Any]) -> Model:
        """The same model with values set at the study files' parameter paths, e.g.
        ``model.with_values({"roller_bearing[*].clearance": "30 um"})``; paths are applied
        in order and the result is validated as a model file would be."""
        return type(self)._checked(self._raw.with_values(list(plain(dict(values)).items())))

    def to_tables(self) -> dict[str, Any]:
        """The model file's tables and keys as a dict, as the file writes them (quantities
        as text with their units): what :meth:`from_dict` reads back. :meth:`to_dict` is
        the validated model in SI instead."""
        return tomllib.loads(self.toml)

    def extended(self, tables: Mapping[str, Any] | Iterable[Part]) -> Model:
        """The same model with more in it, validated again: ``tables`` are the model
        file's tables or parts (:mod:`whirl.parts`); each list (``unbalance``,
        ``roller_bearing``, ``disk``, ...) is appended to the model file's list of that name,
        each other value (``damping``, ``operating``) set. For instance an unbalance on a
        rotor read from ROSS: ``rotor.extended([whirl.Unbalance(node=12, mass="1 g",
        eccentricity="50 mm")])``. To replace a list, edit :meth:`parts` or
        :meth:`to_tables` and give them to :meth:`build` or :meth:`from_dict`."""
        added = tables if isinstance(tables, Mapping) else tables_of(tables)
        merged = self.to_tables()
        for key, value in plain(dict(added)).items():
            if isinstance(value, list):
                merged[key] = [*merged.get(key, []), *value]
            else:
                merged[key] = value
        return type(self).from_dict(merged)

    @property
    def name(self) -> str:
        """The model's name."""
        return self._raw.name

    @property
    def gravity(self) -> float:
        """Gravity along -y, m/s^2 (0 when switched off)."""
        return self.to_dict()["gravity"]

    @property
    def file(self) -> str | None:
        """The file the model was read from, as given, if any."""
        file = self._raw.file
        return None if file is None else str(file)

    @property
    def toml(self) -> str:
        """The model as model-file text (with the edits made by :meth:`with_values`)."""
        return self._raw.toml

    @property
    def node_count(self) -> int:
        """Number of nodes of the mesh."""
        return self._raw.node_count

    @property
    def length(self) -> float:
        """Shaft length, m."""
        return self._raw.length

    @property
    def shaft_mass(self) -> float:
        """Mass of the shaft sections, kg."""
        return self._raw.shaft_mass

    def node_positions(self) -> np.ndarray:
        """Axial positions of the nodes, m."""
        return self._raw.node_positions()

    def node_features(self) -> list[str]:
        """What sits at each node, e.g. ``"disk; bearing A"`` (empty where nothing does)."""
        return self._raw.node_features()

    def bearing_nodes(self) -> list[int]:
        """Nodes that carry a bearing, ascending."""
        return self._raw.bearing_nodes()

    def to_dict(self) -> dict[str, Any]:
        """The validated model in SI units (as whirl holds it, not as the file writes it)."""
        return json.loads(self._raw.to_json())

    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes the model as a model file."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.toml)

    def __reduce__(self):
        # Rebuilt from its text (e.g. on a Dask worker), validated again.
        return (Model.from_toml, (self.toml, self.file))

    def __repr__(self) -> str:
        return repr(self._raw)


def as_model(model: Model | str | os.PathLike[str]) -> Model:
    """A model, or the model read from a file path."""
    if isinstance(model, Model):
        return model
    if isinstance(model, (str, os.PathLike)):
        return Model.from_file(model)
    raise TypeError(f"expected a whirl.Model or a model file path, not {type(model).__name__}")


def _unwritable(value: Any, path: str) -> tuple[str, Any] | None:
    """The first value under ``value`` that a model file cannot hold (NaN, infinity), with
    its key path (``disk[0].mass``): JSON would carry it to the parser, which could only
    name a column of the JSON text. None stays: it is an absent optional key."""
    if isinstance(value, float) and not math.isfinite(value):
        return path or "model", value
    if isinstance(value, Mapping):
        for key, item in value.items():
            found = _unwritable(item, f"{path}.{key}" if path else str(key))
            if found is not None:
                return found
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            found = _unwritable(item, f"{path}[{i}]")
            if found is not None:
                return found
    return None
