"""report.json's numbers as the HTML report shows them: the value at a dotted path, a table cell
that carries the path (``data-key``) and the exact value (``data-value``) and shows it to 6
digits, and the tables built of such cells."""
from __future__ import annotations

import html
import math
from typing import Any, Iterable, Mapping, Sequence


def lookup(report: Mapping[str, Any], key: str) -> Any:
    """The value at a dotted path (list indices as numbers): ``spec.motion.1.lift``."""
    node: Any = report
    for part in key.split("."):
        if isinstance(node, list):
            node = node[int(part)]
        elif isinstance(node, Mapping) and part in node:
            node = node[part]
        else:
            raise KeyError(key)
    return node


def has(report: Mapping[str, Any], key: str) -> bool:
    """Whether report.json has a value at the dotted path ``key``."""
    try:
        lookup(report, key)
        return True
    except (KeyError, IndexError, ValueError):
        return False


def format_number(v: Any) -> str:
    """How a number is shown: 6 significant digits (integers and booleans as they are)."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return str(v)
        return f"{v:.6g}"
    return html.escape(str(v))


def num_cell(report: Mapping[str, Any], key: str) -> str:
    """The ``<td>`` of the value at ``key``: ``data-key`` the path, ``data-value`` the exact value
    (a number's ``repr``; true, false, null as in JSON), the text :func:`format_number`'s; a
    string's cell holds the string and no ``data-value``."""
    v = lookup(report, key)
    if isinstance(v, str):
        return f'<td data-key="{key}">{html.escape(v)}</td>'
    data = "null" if v is None else ("true" if v is True else "false" if v is False else repr(v))
    return f'<td class="num" data-key="{key}" data-value="{data}">{format_number(v)}</td>'


def quantity_table(report: Mapping[str, Any], rows: Iterable[tuple[str, str, str, str | None]]) -> str:
    """Rows (label, key, unit, key of the cam angle or None); rows whose key is absent are left out."""
    out = ['<table class="q"><tr><th>quantity</th><th>value</th><th>unit</th><th>at cam angle [deg]</th></tr>']
    for label, key, unit, at in rows:
        if not has(report, key):
            continue
        at_cell = num_cell(report, at) if at and has(report, at) else "<td></td>"
        out.append(f"<tr><td>{html.escape(label)}</td>{num_cell(report, key)}<td>{html.escape(unit)}</td>"
                   f"{at_cell}</tr>")
    out.append("</table>")
    return "".join(out)


def scalars_table(report: Mapping[str, Any], section: str, exclude: Sequence[str] = ()) -> str:
    """Every scalar of ``report[section]`` (nested dicts flattened) as key/value rows."""
    rows = []

    def walk(node: Any, path: str) -> None:
        if isinstance(node, Mapping):
            for k, v in node.items():
                if path == section and k in exclude:
                    continue
                walk(v, f"{path}.{k}")
        elif not isinstance(node, list):
            label = path[len(section) + 1:].replace("_", " ")
            rows.append(f"<tr><td>{html.escape(label)}</td>{num_cell(report, path)}</tr>")

    walk(report[section], section)
    return '<table class="kv"><tr><th>item</th><th>value</th></tr>' + "".join(rows) + "</table>"


def check_result(report: Mapping[str, Any], name: str) -> Mapping[str, Any] | None:
    """report.json's ``checks.results[name]``, or None when the report has no such check."""
    checks = report.get("checks")
    if not isinstance(checks, Mapping) or not isinstance(checks.get("results"), Mapping):
        return None
    r = checks["results"].get(name)
    return r if isinstance(r, Mapping) else None
