"""The FreeCAD workbench's two sides, checked on the source (issue 21, item 4).

App-side modules — the feature, its properties and solids, the spec's files, the exports, the
checks, the optimiser's model — run in ``freecadcmd`` too and import no Gui-side module (view
providers, commands, task panels, dialogs), counting every import, those inside functions too:
a feature made while the GUI is up gets its view provider through ``view_hook``, where the GUI
registers it.  Nor do they import the GUI's libraries at module level.
"""
from __future__ import annotations

import ast

from .conftest import ROOT

PACKAGE = "cam_workbench.freecad"
FREECAD = ROOT / "cam_workbench" / "freecad"
#: The Gui-side modules: they run with the GUI up only.
GUI_SIDE = frozenset({"view_providers", "commands", "motion_editor", "optimiser_panel", "export_dialog",
                      "qt_compat", "spec_io_gui"})
#: The App-side modules (a dialog's function may sit beside the headless code it shows, importing
#: the GUI's libraries inside that function).
APP_SIDE = frozenset({"__init__", "check_design", "exports", "feature", "install", "optimiser", "part_build",
                      "plots", "properties", "spec_io", "stateless", "step_export", "view_hook"})
#: The GUI's libraries: never imported at an App-side module's top level.
GUI_LIBRARIES = frozenset({"FreeCADGui", "PySide", "PySide2", "PySide6", "shiboken2", "shiboken6"})
#: What an import inside a function may load: FreeCAD's own modules (properties, exports, install
#: and check_design import in any Python too), the GUI's libraries, and matplotlib (optional: the
#: plots).  Anything else is imported at the top of the module.
DEFERRED = frozenset({"FreeCAD", "FreeCADGui", "Part", "PySide", "matplotlib"})
#: Modules that may defer more: ``commands`` loads a command's module (numpy, scipy, the
#: generators) when the command runs, so that activating the workbench stays cheap;
#: ``optimiser``'s comparisons of kinds are being replaced by the body protocol in this same issue
#: (issue 21, item 3), and its imports with them.
DEFER_MORE = {"commands": ("cam_workbench.freecad", "cam_workbench.generators"), "optimiser": ("",)}


def imports(tree: ast.AST) -> list[tuple[int, str, bool]]:
    """Every import of the syntax tree ``tree`` of a module of ``cam_workbench.freecad``:
    (line, the absolute name of each module it loads, whether it is at the module's top level,
    i.e. outside every function).  ``from . import x`` loads ``<package>.x``; relative names are
    resolved against the package."""
    nested: set[int] = set()
    for fn in ast.walk(tree):
        if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            nested |= {id(n) for n in ast.walk(fn) if n is not fn}
    out = []
    package = PACKAGE.split(".")
    for node in ast.walk(tree):
        top = id(node) not in nested
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, top) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # every module here, __init__ too, is in the package: level 1 is the package
                parent = package[:len(package) - (node.level - 1)]
                base = ".".join(parent + ([node.module] if node.module else []))
            out.append((node.lineno, base, top))
            # `from package import module`: each name may itself be a module
            out += [(node.lineno, f"{base}.{a.name}", top) for a in node.names]
    return out


def _sources() -> dict[str, ast.AST]:
    return {p.stem: ast.parse(p.read_text(encoding="utf-8"), str(p)) for p in sorted(FREECAD.glob("*.py"))}


def test_every_module_is_on_one_side():
    """A new module of the workbench says which side it is on (here)."""
    names = set(_sources())
    assert not GUI_SIDE & APP_SIDE
    assert names == GUI_SIDE | APP_SIDE, (f"not classified: {sorted(names - GUI_SIDE - APP_SIDE)}; "
                                          f"gone: {sorted((GUI_SIDE | APP_SIDE) - names)}")


def test_app_side_imports_no_gui_side_module():
    """No App-side module imports a Gui-side one, anywhere in it (inside functions too), nor loads a
    module by a computed name (``importlib``, ``__import__``) that this check could not see."""
    gui = {f"{PACKAGE}.{m}" for m in GUI_SIDE}
    offenders = []
    for name, tree in _sources().items():
        if name not in APP_SIDE:
            continue
        for line, module, _top in imports(tree):
            if module in gui or any(module.startswith(g + ".") for g in gui):
                offenders.append(f"cam_workbench/freecad/{name}.py:{line} imports {module}")
            if module == "importlib" or module.startswith("importlib."):
                offenders.append(f"cam_workbench/freecad/{name}.py:{line} imports {module}")
        calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)
                 and n.func.id == "__import__"]
        offenders += [f"cam_workbench/freecad/{name}.py:{c.lineno} calls __import__" for c in calls]
    assert not offenders, "\n".join(offenders)


def test_app_side_loads_the_gui_libraries_only_inside_functions():
    """An App-side module imports in ``freecadcmd``: FreeCADGui and PySide only inside the
    function that shows a dialog."""
    offenders = [f"cam_workbench/freecad/{name}.py:{line} imports {module} at its top level"
                 for name, tree in _sources().items() if name in APP_SIDE
                 for line, module, top in imports(tree)
                 if top and module.split(".")[0] in GUI_LIBRARIES]
    assert not offenders, "\n".join(offenders)


def test_imports_inside_functions_only_defer_optional_dependencies():
    """An import inside a function defers FreeCAD, the GUI or matplotlib; the package's own modules
    and the generators are imported at the top (no cycle needs hiding: the App side never imports
    the Gui side)."""
    offenders = [f"cam_workbench/freecad/{name}.py:{line} imports {module} inside a function"
                 for name, tree in _sources().items()
                 for line, module, top in imports(tree)
                 if not top and module.split(".")[0] not in DEFERRED
                 and not module.startswith(DEFER_MORE.get(name, ("\0",)))]
    assert not offenders, "\n".join(offenders)


def test_the_checker_sees_every_kind_of_import():
    """The import walker itself, on a module that hides Gui-side imports every way it can."""
    tree = ast.parse("from . import view_providers\n"
                     "def f():\n    from .commands import register\n"
                     "class C:\n    def g(self):\n        import cam_workbench.freecad.motion_editor as m\n"
                     "h = lambda: __import__('x')\n"
                     "from .. import freecad\n"
                     "import FreeCADGui\n")
    got = {(line, module, top) for line, module, top in imports(tree)}
    assert (1, "cam_workbench.freecad.view_providers", True) in got
    assert (3, "cam_workbench.freecad.commands", False) in got
    assert (6, "cam_workbench.freecad.motion_editor", False) in got
    assert (8, "cam_workbench.freecad", True) in got
    assert (9, "FreeCADGui", True) in got
