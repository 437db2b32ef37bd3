"""pint quantities (or any object with ``magnitude``, ``units`` and ``to``) as the model
file writes quantities: text with one of whirl's units where the field takes one, SI
numbers otherwise; and the parts of a model built in code as their tables."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

#: pint's dimensionality -> the unit whirl reads that quantity in (text with a unit).
_UNIT_OF = {
    "[length]": "um",
    "[mass]": "kg",
    "[time]": "s",
    "[length] * [mass] / [time] ** 2": "N",
}


def _is_quantity(value: Any) -> bool:
    return all(hasattr(value, name) for name in ("magnitude", "units", "dimensionality", "to"))


def _speed_unit(units: str) -> str:
    # whirl's Hz is revolutions per second, pint's a plain 1/s (one radian per second):
    # a frequency and an rpm keep their own unit so that neither loses its 2 pi.
    if "revolutions_per_minute" in units or units == "rpm":
        return "rpm"
    return "Hz" if "hertz" in units else "rad/s"


def _text(q: Any) -> str | float:
    dimension = str(q.dimensionality)
    if dimension == "1 / [time]":
        unit = _speed_unit(str(q.units))
    elif dimension == "dimensionless" and any(a in str(q.units) for a in ("degree", "radian")):
        # Angles (an unbalance's phase) are degrees in the model file.
        return float(q.to("degree").magnitude)
    elif dimension in _UNIT_OF:
        unit = _UNIT_OF[dimension]
    else:
        return float(q.to_base_units().magnitude)
    return f"{float(q.to(unit).magnitude)!r} {unit}"


def plain(value: Any) -> Any:
    """``value`` with every quantity in it (at any depth of dicts and lists) as the model
    file writes it, and every part of a model (:class:`whirl.parts.Part`) as its table."""
    if _is_quantity(value):
        return _text(value)
    if hasattr(value, "table") and isinstance(getattr(value, "fields", None), dict):
        # A part (whirl.parts, which builds on this module): its table.
        return plain(value.fields)
    if isinstance(value, Mapping):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value
