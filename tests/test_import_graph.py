"""Imports point one way, checked over the source (issue 21 item 4).

Every module of the one import name is read with :mod:`ast` — ``cam_workbench/``, and the
repository folders ``generators/`` and ``exporters/`` as ``cam_workbench.generators`` and
``cam_workbench.exporters`` — and every ``import``/``from … import`` statement is counted: at
module level, inside functions and inside class bodies alike.  Only the body of an
``if TYPE_CHECKING:`` block is left out (annotations only: it never runs).  An edge goes from the
importing module to the module it names: ``from P import x`` is an edge to ``P.x`` when that is a
module, else to ``P``.  A parent package's ``__init__``, which Python runs before any of its
submodules, is not an edge of its own (it would put every package that re-exports its children
in a cycle with them; import-linter's graph counts the same way).

The rules:

(a) **No cycle**: the graph has no strongly connected component of more than one module.

(b) **An import inside a function (or a class body) defers a heavy optional dependency**, and says
    which on its line or the line above (``# deferred: OCP``).  :data:`DEFERRABLE` lists them:
    the CAD kernel and its front ends (OCP, cadquery, build123d: extras, never requirements);
    FreeCAD's modules and its Qt binding (``FreeCAD``, ``FreeCADGui``, ``Part``, ``PySide*``: they
    exist only inside FreeCAD); the engines of the ``[dask]`` extra (dask, distributed, pyarrow,
    and psutil that distributed brings, read on its workers); CairoSVG (the ``[png]`` extra); and
    three requirements that only some outputs or commands use and that are slow to import
    (measured on a quiet machine, interpreter start included: ezdxf 0.6 s, matplotlib 0.35 s,
    nlopt 0.25 s) — deferring them keeps ``import cam_workbench.generators`` and the FreeCAD
    workbench at numpy and scipy, and the command line's start free of them.  Of scipy, the
    subpackages :data:`DEFERRED_SCIPY` lists (each with its reason) may be deferred to the
    function that needs one, the comment naming it (``# deferred: scipy.spatial``).  Not in the
    lists: rich (a requirement, 0.05 s the same way, the command line's own), numpy (every
    design's own), the standard library, and
    every module of the project — a project module imported late hides a cycle or an upward
    import.  One exception, by its construction: a package ``__init__``'s module ``__getattr__``
    (PEP 562) may import that package's own submodule — the lazy API of ``cam_workbench`` (``from
    cam_workbench import Cam`` loads the API layer when asked; ``import
    cam_workbench.generators`` does not); and so may the methods FreeCAD calls when the user first
    opens the workbench (:data:`HOOKS`: FreeCAD runs ``mod/InitGui.py`` at every start with
    ``exec()``, whose module-level names its methods cannot see, so ``Initialize`` imports the
    workbench's commands); and so may the workbench's commands (:data:`LATE_LOADERS`): FreeCAD
    imports ``cam_workbench.freecad.commands`` when the workbench is activated, and each command
    loads its own module (numpy, scipy, the generators, matplotlib, the task panels) only when it
    runs, so that activating the workbench stays cheap (``tests/test_freecad_gui.py``); and so may
    the command line's entry (``cam_workbench.cli``), which parses the arguments with the
    commands' declarations alone (``cam_workbench.commands.parsers``: ``--help`` and argument
    errors load no command) and loads the running of commands (``cam_workbench.commands.dispatch``)
    only to run one, which loads that command's module alone.  Each says what it defers; their
    edges still count for (a).

    Loading a module by its name (``importlib.import_module``, ``__import__``), which this reading
    cannot follow, is left to the two loaders of optional dependencies: the OCP adaptor and
    ``cam_workbench.extras`` (CadQuery, build123d).

(c) **Layers point down**: ``cam_workbench.generators`` imports nothing of the project outside
    itself; ``cam_workbench.exporters`` only the generators and the kernel; the kernel
    (``cam_workbench.kernel``, the only OCP importer) only the generators; the FreeCAD
    workbench's App side never its Gui side (:data:`FREECAD_GUI_SIDE`).

``python tests/test_import_graph.py`` prints the counts (cycles; imports inside functions, by area).
"""
from __future__ import annotations

import ast
import functools
import io
import sys
import tokenize
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

if __package__:
    from .conftest import ROOT
else:  # run as a script
    ROOT = Path(__file__).resolve().parent.parent

#: repository folder → its import name
FOLDERS = {"cam_workbench": "cam_workbench", "generators": "cam_workbench.generators",
           "exporters": "cam_workbench.exporters"}

#: the heavy optional dependencies an import inside a function may defer (rule (b), the docstring)
DEFERRABLE = frozenset({
    "OCP", "cadquery", "build123d",                       # the CAD kernel and its front ends
    "FreeCAD", "FreeCADGui", "Part", "PySide", "PySide2", "PySide6",  # inside FreeCAD only
    "matplotlib", "ezdxf",                                # plots; DXF
    "nlopt",                                              # the optimiser's solvers
    "dask", "distributed", "pyarrow",                     # the studies' parallel runs, Parquet
    "psutil",                                             # distributed's own, read on a Dask worker
    "cairosvg",                                           # PNG figures on request (the [png] extra)
})

#: scipy's subpackages that only some computations use (rule (b)): an import inside the function
#: that needs one may defer it, so that ``import cam_workbench.generators``, the FreeCAD workbench
#: and ``cam-workbench check`` of a plate cam load numpy alone (issue 22 item 3).  Each with its
#: reason and the CPU time its import adds beside numpy and scipy.linalg (measured on a quiet
#: machine, the fastest of three; scipy.linalg's beside numpy).
DEFERRED_SCIPY = {
    "scipy.linalg": "LAPACK's pivoting banded solve of a tridiagonal system that is not diagonally dominant "
                    "(the PH spline's own are solved by cyclic reduction in numpy): 0.25 s",
    "scipy.interpolate": "the drawings' cubic fits and a cylindrical cam's walls: 0.14 s (it loads scipy.optimize)",
    "scipy.optimize": "the follower dynamics' root finding: 0.12 s",
    "scipy.spatial": "nearest-point distances of the drawings and a cylindrical cam's tool path: 0.06 s",
    "scipy.sparse": "the least-squares fits of a tabulated law and of a B-spline pitch curve: 0.015 s with "
                    "scipy.sparse.linalg",
}

#: (module, method) that FreeCAD calls late, where the workbench's own modules are imported (rule (b))
HOOKS = frozenset({("cam_workbench.freecad.mod.InitGui", "CamWorkbench.Initialize")})

#: module → the project packages its functions may import late (rule (b)): the workbench's commands,
#: imported when the workbench is activated, load what a command needs when it runs; the command
#: line's entry loads the running of commands when one is to run, and that loads the one command's module
LATE_LOADERS = {"cam_workbench.freecad.commands": ("cam_workbench.freecad", "cam_workbench.generators"),
                "cam_workbench.cli": ("cam_workbench.commands",),
                "cam_workbench.commands.dispatch": ("cam_workbench.commands",)}

#: the layers (rule (c)): a module under the key imports, of the project, only modules under these
LAYERS = {
    "cam_workbench.generators": ("cam_workbench.generators",),
    "cam_workbench.exporters": ("cam_workbench.exporters", "cam_workbench.generators", "cam_workbench.kernel"),
    "cam_workbench.kernel": ("cam_workbench.kernel", "cam_workbench.generators"),
}

#: The FreeCAD workbench's two sides (rule (c); ``tests/test_freecad_layering.py`` holds every
#: module to one of them).  The Gui side runs with the GUI up only: its view providers, commands,
#: task panels, dialogs, Qt helpers, the GUI's spec importer and ``mod/InitGui.py``.
FREECAD_GUI_SIDE = frozenset(f"cam_workbench.freecad.{m}" for m in (
    "commands", "export_dialog", "inspection_panel", "machine_panel", "motion_editor", "optimiser_panel", "qt_compat",
    "spec_io_gui", "view_providers", "mod.InitGui"))
#: The App side runs in ``freecadcmd`` too and imports no Gui-side module: the feature, its
#: properties and Part builders, the spec's files, the exports, the checks, the plots, the
#: optimiser's model, the install script, ``mod/Init.py``.  A module whose headless function has a
#: dialog beside it (``check_design.show_report``) is App side and imports FreeCADGui and PySide
#: inside that function only.
FREECAD_APP_SIDE = frozenset(["cam_workbench.freecad"] + [f"cam_workbench.freecad.{m}" for m in (
    "bodies", "check_design", "exports", "feature", "inspection_doc", "install", "machine_doc", "machine_parts",
    "optimiser", "part_build", "part_cylindrical", "part_indexer", "part_spatial_indexer", "plots", "properties",
    "spec_io", "stateless", "step_export", "tolerance_panel", "view_hook", "mod.Init")])


@dataclass(frozen=True)
class Import:
    """One import statement's target, where it stands and why (its comments)."""

    module: str        #: the importing module
    target: str        #: the absolute name imported (a module, or the package a name comes from)
    line: int
    place: str         #: "module", "function" or "class"
    scope: str         #: the enclosing definitions ("" at module level; "CamWorkbench.Initialize")
    comment: str       #: the comments on its lines and the line above


@functools.lru_cache(maxsize=None)
def modules() -> dict[str, Path]:
    """Every module of the one import name → its file."""
    found = {}
    for folder, name in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT / folder).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join((name,) + parts)] = path
    return found


def _comments(text: str) -> dict[int, str]:
    out: dict[int, str] = {}
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type == tokenize.COMMENT:
            out[tok.start[0]] = tok.string
    return out


def _is_type_checking(node: ast.If) -> bool:
    t = node.test
    return (isinstance(t, ast.Name) and t.id == "TYPE_CHECKING") or (
        isinstance(t, ast.Attribute) and t.attr == "TYPE_CHECKING")


def imports_of(name: str, path: Path, known: set[str]) -> list[Import]:
    """The imports of module ``name`` (file ``path``), each resolved to an absolute target."""
    text = path.read_text(encoding="utf-8")
    comments = _comments(text)
    is_package = path.name == "__init__.py"
    found: list[Import] = []

    def resolve(node: ast.ImportFrom) -> str:
        if not node.level:
            return node.module or ""
        base = name.split(".")
        base = base if is_package else base[:-1]
        base = base[:len(base) - (node.level - 1)]
        return ".".join(base + ([node.module] if node.module else []))

    def add(node: ast.stmt, target: str, place: str, scope: str) -> None:
        text_ = " ".join(comments.get(i, "") for i in range(node.lineno - 1, (node.end_lineno or node.lineno) + 1))
        found.append(Import(name, target, node.lineno, place, scope, text_))

    def visit(node: ast.AST, place: str, scope: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child):
                for sub in child.orelse:
                    visit_one(sub, place, scope)
                continue
            visit_one(child, place, scope)

    def visit_one(child: ast.AST, place: str, scope: str) -> None:
        if isinstance(child, ast.Import):
            for alias in child.names:
                add(child, alias.name, place, scope)
        elif isinstance(child, ast.ImportFrom):
            base = resolve(child)
            for alias in child.names:
                sub = f"{base}.{alias.name}"
                add(child, sub if sub in known else base, place, scope)
        elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            visit(child, "function", f"{scope}.{getattr(child, 'name', '<lambda>')}".lstrip("."))
        elif isinstance(child, ast.ClassDef):
            visit(child, "function" if place == "function" else "class", f"{scope}.{child.name}".lstrip("."))
        elif isinstance(child, ast.If) and _is_type_checking(child):
            for sub in child.orelse:
                visit_one(sub, place, scope)
        else:
            visit(child, place, scope)

    visit(ast.parse(text, filename=str(path)), "module", "")
    return found


def project_target(target: str, known: set[str]) -> str | None:
    """The project module an import's target is (its longest known prefix), or None."""
    parts = target.split(".")
    for i in range(len(parts), 0, -1):
        candidate = ".".join(parts[:i])
        if candidate in known:
            return candidate
    return None


@functools.lru_cache(maxsize=None)
def all_imports() -> tuple[Import, ...]:
    """Every import statement's targets, of every module."""
    mods = modules()
    known = set(mods)
    return tuple(imp for name, path in mods.items() for imp in imports_of(name, path, known))


def graph(imports: tuple[Import, ...]) -> dict[str, set[str]]:
    """Project module → the project modules it imports (every statement, TYPE_CHECKING aside)."""
    known = set(modules())
    edges: dict[str, set[str]] = {m: set() for m in known}
    for imp in imports:
        target = project_target(imp.target, known)
        if target is not None and target != imp.module:
            edges[imp.module].add(target)
    return edges


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    counter = 0
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(edges) + 100))

    def strong(v: str) -> None:
        nonlocal counter
        index[v] = low[v] = counter
        counter += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            strong(v)
    return sorted(out, key=lambda c: (-len(c), c))


def area(module: str) -> str:
    """The area a module belongs to, for the counts."""
    for prefix in ("cam_workbench.generators", "cam_workbench.exporters", "cam_workbench.freecad",
                   "cam_workbench.commands", "cam_workbench.kernel"):
        if module == prefix or module.startswith(prefix + "."):
            return prefix
    return "cam_workbench (rest)"


def deferral_problem(imp: Import) -> str | None:
    """Why an import inside a function or class body breaks rule (b), or None when it keeps it."""
    lazy = imp.scope == "__getattr__" and modules()[imp.module].name == "__init__.py" \
        and imp.target.startswith(imp.module + ".")
    late = imp.target.startswith(LATE_LOADERS.get(imp.module, ("\0",)))
    if lazy or late or (imp.module, imp.scope) in HOOKS:
        # a package's PEP 562 lazy submodule, a FreeCAD hook, a command's module: the comment
        # says what it defers
        return None if "defer" in imp.comment.lower() else "no '# deferred: …' comment"
    scipy = [m for m in DEFERRED_SCIPY if imp.target == m or imp.target.startswith(m + ".")]
    root = scipy[0] if scipy else imp.target.split(".")[0]
    if root not in DEFERRABLE and not scipy:
        return f"{imp.target} is not a heavy optional dependency"
    if root.lower() not in imp.comment.lower():
        return f"no comment naming {root} on its line or the line above"
    return None


def _where(imp: Import) -> str:
    path = modules()[imp.module]
    return f"{path.relative_to(ROOT).as_posix()}:{imp.line}"


def test_no_import_cycle():
    found = cycles(graph(all_imports()))
    assert not found, "import cycles (strongly connected components):\n" + "\n".join(
        f"  {len(c)}: " + " ".join(c) for c in found)


def test_imports_inside_functions_defer_heavy_optional_dependencies():
    bad = [f"{_where(imp)} {imp.place}: {problem}" for imp in all_imports() if imp.place != "module"
           for problem in [deferral_problem(imp)] if problem]
    assert not bad, f"{len(bad)} imports inside functions or class bodies:\n" + "\n".join(bad)


#: the modules that may load a module by its name (rule (b))
NAME_LOADERS = frozenset({"cam_workbench.kernel.ocp", "cam_workbench.extras"})


def test_modules_are_loaded_by_name_only_in_the_loaders():
    bad = []
    for name, path in modules().items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and (
                    (isinstance(node.func, ast.Attribute) and node.func.attr == "import_module")
                    or (isinstance(node.func, ast.Name) and node.func.id in ("__import__", "import_module"))):
                if name not in NAME_LOADERS:
                    bad.append(f"{path.relative_to(ROOT).as_posix()}:{node.lineno}")
    assert not bad, "modules loaded by name outside the loaders: " + ", ".join(bad)


def test_layers_point_down():
    imports = all_imports()
    known = set(modules())
    bad = []
    for imp in imports:
        target = project_target(imp.target, known)
        if target is None:
            continue
        for layer, allowed in LAYERS.items():
            if imp.module == layer or imp.module.startswith(layer + "."):
                if not any(target == a or target.startswith(a + ".") for a in allowed):
                    bad.append(f"{_where(imp)}: {layer} imports {target}")
    assert not bad, "\n".join(bad)


def test_freecad_app_side_imports_no_gui_side():
    """The App side of the workbench runs in ``freecadcmd`` (no GUI): none of its modules imports
    a Gui-side module, at any level."""
    known = set(modules())
    assert FREECAD_GUI_SIDE <= known, sorted(FREECAD_GUI_SIDE - known)
    bad = [f"{_where(imp)}: {imp.module} imports {target}" for imp in all_imports()
           if imp.module.startswith("cam_workbench.freecad") and imp.module not in FREECAD_GUI_SIDE
           for target in [project_target(imp.target, known)] if target in FREECAD_GUI_SIDE]
    assert not bad, "\n".join(bad)


def test_the_command_line_starts_without_the_deferred_dependencies():
    """What the deferring is for: the command line's parser, every command's module, the API's
    module and the kernel load none of the deferred dependencies until a command or a method
    needs one."""
    import subprocess

    code = ("import sys, cam_workbench.cli, cam_workbench.cam, cam_workbench.kernel.step\n"
            "from cam_workbench.commands.dispatch import RUNNERS\n"
            "cam_workbench.cli.build_parser()\n"
            "runners = [load() for load in RUNNERS.values()]   # every command's module\n"
            f"print(','.join(sorted(m for m in {sorted(DEFERRABLE)!r} if m in sys.modules)))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "", f"loaded at start: {res.stdout.strip()}"


def test_a_plate_cams_check_loads_no_scipy():
    """``cam-workbench check`` of the built-in plate cams (and their design through the API) runs
    on numpy alone: scipy's import (0.25 s with scipy.linalg, the floor issue 22 measures
    ``check`` against) is left to the computations :data:`DEFERRED_SCIPY` names."""
    import subprocess

    code = ("import sys, io, contextlib\n"
            "from cam_workbench.cli import main\n"
            "from cam_workbench.generators import design_cam\n"
            "from cam_workbench.generators.spec.examples import example_spec\n"
            "for ex in ('default', 'paper', 'groove', 'conjugate'):\n"
            "    with contextlib.redirect_stdout(io.StringIO()):\n"
            "        assert main(['check', '--example', ex]) in (0, 3)\n"
            "    design_cam(example_spec(ex)).summary()\n"
            "print(','.join(sorted(m for m in sys.modules if m.split('.')[0] == 'scipy')))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "", f"loaded: {res.stdout.strip()}"


def test_the_graph_sees_every_import():
    """The reader itself: a known upward import, a known cycle and a deferred import are found."""
    text = ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import x.hidden\n"
            "import json\nfrom . import b\nclass K:\n    import c\n"
            "def f():\n    # deferred: OCP\n    from OCP import gp\n    from .. import d\n")
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "a.py"
        p.write_text(text)
        got = imports_of("pkg.sub.a", p, {"pkg.sub.b", "pkg.d"})
    assert [(i.target, i.place) for i in got] == [
        ("typing", "module"), ("json", "module"), ("pkg.sub.b", "module"), ("c", "class"), ("OCP", "function"),
        ("pkg.d", "function")]
    assert "OCP" in got[4].comment
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    # a workbench module that reaches the Gui side every way it can
    text = ("from . import view_providers\n"
            "def f():\n    from .commands import register\n"
            "class C:\n    def g(self):\n        import cam_workbench.freecad.motion_editor as m\n"
            "from .. import freecad\n"
            "import FreeCADGui\n")
    gui = {"cam_workbench.freecad.view_providers", "cam_workbench.freecad.commands",
           "cam_workbench.freecad.motion_editor"}
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "a.py"
        p.write_text(text)
        got = imports_of("cam_workbench.freecad.a", p, gui | {"cam_workbench.freecad", "cam_workbench"})
    assert [(i.line, i.target, i.place, i.scope) for i in got] == [
        (1, "cam_workbench.freecad.view_providers", "module", ""),
        (3, "cam_workbench.freecad.commands", "function", "f"),
        (6, "cam_workbench.freecad.motion_editor", "function", "C.g"),
        (7, "cam_workbench.freecad", "module", ""), (8, "FreeCADGui", "module", "")]


def counts() -> str:
    """Cycles and imports inside functions (or class bodies), by area: the numbers of the issue."""
    imports = all_imports()
    found = cycles(graph(imports))
    inner = [i for i in imports if i.place != "module"]
    bad = [i for i in inner if deferral_problem(i)]
    lines = [f"modules: {len(modules())}; import statements' targets: {len(imports)}",
             f"cycles: {len(found)} (sizes {[len(c) for c in found]})"]
    lines += [f"  {len(c)}: {' '.join(c)}" for c in found]
    statements = {(i.module, i.line) for i in inner}
    bad_statements = {(i.module, i.line) for i in bad}
    lines.append(f"import statements inside functions or class bodies: {len(statements)} "
                 f"({len(inner)} names); breaking rule (b): {len(bad_statements)}")
    by_area = Counter(area(m) for m, _ in statements)
    by_area_bad = Counter(area(m) for m, _ in bad_statements)
    lines += [f"  {a}: {n} (breaking (b): {by_area_bad[a]})" for a, n in sorted(by_area.items())]
    return "\n".join(lines)


if __name__ == "__main__":
    print(counts())
