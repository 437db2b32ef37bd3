"""A model given as tables (a dict, or parts) written as model-file text, in the order given,
with the key path of each line, so that the library's located messages name the key
(``disk[0].mass``) rather than a line of text the user never saw."""

from __future__ import annotations

import json
import numbers
import re
from collections.abc import Mapping
from typing import Any

from . import _whirl

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
#: How the library starts a message located in text without a file name.
_LOCATION = re.compile(r"^line (\d+), column \d+: ")


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        #: The key path each line holds (`shaft[0].length`), "" for none.
        self.paths: list[str] = []

    def line(self, text: str, path: str) -> None:
        self.lines.append(text)
        self.paths.append(path)

    def table(self, table: Mapping[str, Any], path: str, header: tuple[str, ...]) -> None:
        """A table's keys, then its tables and arrays of tables (as TOML requires)."""
        for key, value in table.items():
            if value is not None and not _is_table(value) and not _is_tables(value):
                try:
                    self.line(f"{_key(key)} = {_value(value)}", _join(path, key))
                except _Unwritable as e:
                    raise _whirl.InputError(
                        f"`{_join(path, key)}`: {e}\n  help: give a number, text with a unit, "
                        "a bool, a list or a table"
                    ) from None
        for key, value in table.items():
            inner, named = _join(path, key), (*header, _key(key))
            if _is_table(value):
                self.line("", "")
                self.line(f"[{'.'.join(named)}]", inner)
                self.table(value, inner, named)
            elif _is_tables(value):
                for i, item in enumerate(value):
                    self.line("", "")
                    self.line(f"[[{'.'.join(named)}]]", f"{inner}[{i}]")
                    self.table(item, f"{inner}[{i}]", named)


def model_text(tables: Mapping[str, Any]) -> tuple[str, list[str]]:
    """The model-file text of ``tables`` (plain values: no quantities, no parts) and the key
    path of each of its lines."""
    writer = _Writer()
    writer.table(tables, "", ())
    return "\n".join(writer.lines) + "\n", writer.paths


def located(message: str, paths: list[str]) -> str:
    """A library message located at a line of text written by :func:`model_text`, with the
    line's key path in place of its line and column (unless the message names its key)."""
    found = _LOCATION.match(message)
    if found is None:
        return message
    rest = message[found.end() :]
    line = int(found.group(1))
    path = paths[line - 1] if 0 < line <= len(paths) else ""
    if rest.startswith("`") or not path:
        return rest
    return f"`{path}`: {rest}"


def _is_table(value: Any) -> bool:
    return isinstance(value, Mapping)


def _is_tables(value: Any) -> bool:
    return isinstance(value, (list, tuple)) and len(value) > 0 and all(map(_is_table, value))


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _key(key: str) -> str:
    return key if _BARE_KEY.fullmatch(key) else json.dumps(key)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        # repr is the shortest text that reads back as the same float (1e-05, 211000000000.0).
        return repr(float(value))
    if isinstance(value, str):
        # A JSON string is a TOML basic string: the same escapes.
        return json.dumps(value)
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items() if v is not None) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    raise _Unwritable(f"{type(value).__name__} {value!r} has no place in a model file")


class _Unwritable(ValueError):
    """A value that model-file text cannot hold (None in a list, an object)."""
