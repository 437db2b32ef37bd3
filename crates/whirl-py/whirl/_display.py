"""How a result shows itself in a notebook: a one-line repr, an HTML summary with the
heads of its tables, ``.plot()`` drawing its figures with matplotlib (:mod:`whirl.plot`),
and ``.save_figures()`` writing the command line's PNG and SVG files."""

from __future__ import annotations

import html
import json
import os
from typing import Any

#: Summary keys every result has (which command, which whirl, which model): the repr and
#: the HTML name the command and the model already.
_HEAD_KEYS = ("command", "whirl_version", "model_file", "model_name")
#: How many summary values the repr shows, and how many rows of each table the HTML.
_REPR_VALUES = 3
_HTML_ROWS = 5
#: Longest text of one summary value in the HTML (a list of 161 speeds would fill a page).
_HTML_VALUE_CHARS = 120


def _scalar(value: Any) -> bool:
    return isinstance(value, (bool, int, float, str)) or value is None


def _shown(value: Any, limit: int) -> str:
    """A summary value as short text: scalars as they are, lists and tables abbreviated."""
    if _scalar(value):
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
    else:
        text = json.dumps(value, default=str)
    return text if len(text) <= limit else text[: limit - 3] + "..."


class Figured:
    """A result with the command line's figures as specifications (``figure_specs()``):
    one by name, and all of them saved as the command line saves them."""

    __slots__ = ()

    def figure_specs(self) -> list[dict[str, Any]]:
        """The command line's figures of this result as specifications, in its order: dicts
        of ``name`` (the files' stem), ``speeds`` (where it shows speeds) and ``figure`` (its
        ``kind`` and what it shows: series, axes, marks, labels), defined once in Rust for
        the command line, :meth:`save_figures` and :func:`whirl.plot.draw`."""
        raise NotImplementedError

    def _spec_names(self) -> tuple[str, ...]:
        return tuple(spec["name"] for spec in self.figure_specs())

    def figure_spec(self, name: str) -> dict[str, Any]:
        """The command line's figure ``name`` as its specification: ``name``, ``speeds``
        and ``figure``, what :func:`whirl.plot.draw` draws."""
        specs = self.figure_specs()
        for spec in specs:
            if spec["name"] == name:
                return spec
        raise ValueError(f"no command line figure `{name}` of a {type(self).__name__}: "
                         f"its figures are {[s['name'] for s in specs]}")

    def save_figures(self, folder: str | os.PathLike[str], rpm: bool = False) -> list[str]:
        """Writes the command line's figures of this result into ``folder`` (created if
        needed), each as ``<name>.png`` and ``<name>.svg``, drawn by the same code as the
        command line's (speeds in rpm when ``rpm``, as ``--rpm``); returns the paths
        written."""
        from . import _whirl

        return [os.fspath(p) for p in _whirl.save_figures(self.figure_specs(), folder, rpm)]


class Display(Figured):
    """Notebook display of a result whose report is ``self._report()``: its command, model,
    summary (``to_dict()``) and tables (``columns(name)``). ``_figures`` names the functions of
    :mod:`whirl.plot` that draw this result, the default first."""

    __slots__ = ()
    _figures: tuple[str, ...] = ()

    def _report(self) -> Any:
        raise NotImplementedError

    def _table_shapes(self) -> list[tuple[str, int, int]]:
        """(name, rows, columns) of each table."""
        report = self._report()
        shapes = []
        for name in report.tables:
            columns = report.columns(name)
            rows = len(next(iter(columns.values()))) if columns else 0
            shapes.append((name, rows, len(columns)))
        return shapes

    def _key_values(self) -> list[tuple[str, Any]]:
        summary = self._report().to_dict()
        return [(k, v) for k, v in summary.items() if k not in _HEAD_KEYS]

    def __repr__(self) -> str:
        report = self._report()
        values = [(k, v) for k, v in self._key_values() if _scalar(v)][:_REPR_VALUES]
        shown = "".join(f", {k}={_shown(v, 40)}" for k, v in values)
        tables = ", ".join(f"{name} [{rows}x{cols}]" for name, rows, cols in self._table_shapes())
        return (
            f"<whirl.{type(self).__name__} {report.command} of {report.model.name!r}{shown}; "
            f"tables: {tables}>"
        )

    def _repr_html_(self) -> str:
        report = self._report()
        rows = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(_shown(v, _HTML_VALUE_CHARS))}</td></tr>"
            for k, v in self._key_values()
        )
        parts = [
            f"<div><b>whirl {html.escape(report.command)}</b> of "
            f"<i>{html.escape(report.model.name)}</i> ({type(self).__name__})",
            f"<table>{rows}</table>",
        ]
        for name, count, cols in self._table_shapes():
            parts.append(
                f"<details><summary>table <code>{html.escape(name)}</code>: {count} rows, "
                f"{cols} columns (<code>to_pandas({name!r})</code>)</summary>"
                f"{_table_head_html(report.columns(name))}</details>"
            )
        parts.append("</div>")
        return "".join(parts)

    def plot(self, kind: str | None = None, **options: Any) -> Any:
        """Draws the result with matplotlib and returns the Axes: ``kind`` is one of
        :attr:`figures` (default the first). The command line's figures are drawn from
        their specification (:func:`whirl.plot.draw`; ``ax=`` to draw on given Axes), the
        others by the function of :mod:`whirl.plot` of that name, which takes ``options``."""
        from . import plot

        figures = self.figures
        if not figures:
            raise NotImplementedError(f"whirl.plot has no figure of a {type(self).__name__}")
        name = figures[0] if kind is None else kind
        if name not in figures:
            raise ValueError(f"no figure `{name}` of a {type(self).__name__}: its figures are {list(figures)}")
        if name in self._spec_names():
            return plot.draw(self.figure_spec(name), **options)
        return getattr(plot, name)(self, **options)

    @property
    def figures(self) -> tuple[str, ...]:
        """The figures ``plot(kind)`` draws of this result, the default first: the command
        line's (as it names their files), then those only :mod:`whirl.plot` draws."""
        names = self._spec_names()
        return names + tuple(f for f in self._figures if f not in names)

    def figure_specs(self) -> list[dict[str, Any]]:
        return self._report().figure_specs()


def _table_head_html(columns: dict[str, Any]) -> str:
    """The first rows of a table as HTML, from its columns."""
    names = list(columns)
    head = "".join(f"<th>{html.escape(n)}</th>" for n in names)
    count = len(columns[names[0]]) if names else 0
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(_cell(columns[n][i]))}</td>" for n in names) + "</tr>"
        for i in range(min(count, _HTML_ROWS))
    )
    more = f"<p>... {count - _HTML_ROWS} more rows</p>" if count > _HTML_ROWS else ""
    return f"<table><tr>{head}</tr>{body}</table>{more}"


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float) or hasattr(value, "dtype") and value.dtype.kind == "f":
        return f"{float(value):.6g}"
    return str(value)
