"""Kinds are plug-ins (issue 21 item 3): no code branches on a kind's name outside the registry
(``generators/kinds/``), the spec declarations (``generators/spec/``) and the kind's own modules.

A *kind literal* is a value of the spec's kind choices — ``cam.body``, ``follower.kind``,
``follower.motion``, ``pitch.representation`` — read from the declarations, so a new kind is
covered the day it is declared.  A *comparison* against one is ``==``/``!=``/``is``, ``in``/``not in``
(either side), a ``match``/``case`` value, or a dict literal keyed by kind names (dispatch on the
kind string).  Every such comparison is counted with the AST of every module under
``generators/``, ``exporters/`` and ``cam_workbench/``; the count is printed (``pytest -s``).

A kind's own modules are the module that defines its registered class and the modules the class
lists in its ``modules`` declaration (e.g. the cylindrical body's machining and optimiser model):
there a kind may name itself, never another kind.
"""
from __future__ import annotations

import ast
import importlib
import inspect
from collections import Counter
from pathlib import Path

from .conftest import ROOT

SCANNED = ("generators", "exporters", "cam_workbench")
#: the comparisons allowed outside: none (89 on main before the registry)
REMAINING = 0
#: where every kind literal may be compared: the registry and the spec declarations
FREE = ("generators/kinds/", "generators/spec/")


def kind_literals() -> frozenset[str]:
    """The values of the spec's kind choices (cam.body, follower.kind/motion, pitch.representation)."""
    from cam_workbench.generators.spec.cam import CamSection
    from cam_workbench.generators.spec.follower import FollowerSection
    from cam_workbench.generators.spec.pitch import PitchSection
    from cam_workbench.generators.spec.params import params_of

    values: set[str] = set()
    for cls, name in ((CamSection, "body"), (FollowerSection, "kind"), (FollowerSection, "motion"),
                      (PitchSection, "representation")):
        values.update(params_of(cls)[name].choices)
    return frozenset(values)


def own_modules() -> dict[str, frozenset[str]]:
    """Repository path → the kind literals it owns (the kind's own modules, from the registry)."""
    try:
        kinds = importlib.import_module("cam_workbench.generators.kinds")
    except ModuleNotFoundError:
        return {}
    out: dict[str, set[str]] = {}
    for plugin, names in kinds.own_modules():
        for mod in names:
            path = Path(inspect.getfile(importlib.import_module(mod))).resolve().relative_to(ROOT).as_posix()
            out.setdefault(path, set()).update(plugin)
    return {p: frozenset(v) for p, v in out.items()}


def _strs(node: ast.AST) -> list[str]:
    """The string constants of a constant or of a tuple/list/set of constants."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e.value for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
    return []


#: what else a kind's name can be: a motion law ("bspline" is also a lift law) and a prism's role
#: ("plate") — a comparison whose other side reads one of these fields compares that, not a kind
OTHER_NAMES = frozenset({"law", "role"})


def _field(node: ast.AST) -> str | None:
    """The field an operand reads: ``law``, ``x.law``, ``x["law"]``, ``x.get("law")`` → "law"."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant):
        return str(node.slice.value)
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get"
            and node.args and isinstance(node.args[0], ast.Constant)):
        return str(node.args[0].value)
    return None


def comparisons(tree: ast.AST, literals: frozenset[str]) -> list[tuple[int, frozenset[str]]]:
    """(line, kind literals compared) of every comparison against a kind literal in ``tree``."""
    found: list[tuple[int, frozenset[str]]] = []
    for node in ast.walk(tree):
        named: list[str] = []
        if isinstance(node, ast.Compare):
            sides = (node.left, *node.comparators)
            if any(_field(side) in OTHER_NAMES for side in sides):
                continue
            for side in sides:
                named += _strs(side)
        elif isinstance(node, ast.match_case):
            for sub in ast.walk(node.pattern):
                if isinstance(sub, ast.MatchValue):
                    named += _strs(sub.value)
        elif isinstance(node, ast.Dict):
            named += [k.value for k in node.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        hit = frozenset(n for n in named if n in literals)
        if hit:
            found.append((node.lineno if hasattr(node, "lineno") else node.pattern.lineno, hit))
    return found


def offences() -> list[tuple[str, int, frozenset[str]]]:
    """(path, line, literals) of every kind-literal comparison outside where it may be."""
    literals = kind_literals()
    owned = own_modules()
    out = []
    for top in SCANNED:
        for path in sorted((ROOT / top).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            if rel.startswith(FREE):
                continue
            for line, hit in comparisons(ast.parse(path.read_text(), rel), literals):
                if not hit <= owned.get(rel, frozenset()):
                    out.append((rel, line, hit))
    return out


def test_the_scanner_sees_every_form():
    """The scanner itself, on code written for the test: each form counts once, other strings never."""
    src = ("a == 'plate'\n'roller' != b\nc in ('groove', 'x')\n'flat' in d\n"
           "match e:\n    case 'knife':\n        pass\n    case 'other':\n        pass\n"
           "f = {'oscillating': 1, 'y': 2}\ng == 'rise'\nh = 'plate'\nk(body='cylindrical')\n"
           "seg.law == 'bspline'\nrow.get('law') == 'bspline'\np.role == 'plate'\nlaw == 'bspline'\n")
    lits = frozenset({"plate", "roller", "groove", "flat", "knife", "oscillating", "cylindrical"})
    got = comparisons(ast.parse(src), lits)
    assert [line for line, _ in got] == [1, 2, 3, 4, 6, 10]


def test_no_kind_literal_is_compared_outside_its_modules():
    found = offences()
    files = Counter(p for p, _, _ in found)
    print(f"\nkind-literal comparisons outside the registry, the spec declarations and the kinds' own "
          f"modules: {len(found)} in {len(files)} files")
    for path, n in files.most_common():
        print(f"  {n:3d}  {path}")
    assert len(found) <= REMAINING, "\n".join(f"{p}:{n}: compares {', '.join(sorted(h))}" for p, n, h in found)
