"""The FreeCAD workbench's two sides, checked on the source (issue 21, item 4).

App-side modules — the feature, its properties and solids, the spec's files, the exports, the
checks, the plots, the optimiser's model — run in ``freecadcmd`` too and import no Gui-side
module (view providers, commands, task panels, dialogs), counting every import, those inside
functions too (``tests/test_import_graph.py::test_freecad_app_side_imports_no_gui_side``): a
feature made while the GUI is up gets its view provider through ``view_hook``, where the GUI
registers it.  Nor do they import the GUI's libraries at module level.  The two lists are
:data:`~tests.test_import_graph.FREECAD_GUI_SIDE` and ``FREECAD_APP_SIDE`` (one source), and the
imports are read by the same reader as the whole tree's import graph.
"""
from __future__ import annotations

import ast

from .test_import_graph import (FREECAD_APP_SIDE, FREECAD_GUI_SIDE, HOOKS, LATE_LOADERS, _where, all_imports,
                                modules)

PACKAGE = "cam_workbench.freecad"
#: The GUI's libraries: never imported at an App-side module's top level.
GUI_LIBRARIES = frozenset({"FreeCADGui", "PySide", "PySide2", "PySide6", "shiboken2", "shiboken6"})
#: What an import inside a function of the workbench may load: FreeCAD's own modules (part_build,
#: check_design, exports, motion_editor and qt_compat import in any Python too), the GUI's
#: libraries, and matplotlib (optional: the plots).  Anything else is imported at the top of the
#: module — but for a package's lazy ``__getattr__``, ``mod/InitGui.py``'s hook and the commands'
#: modules (``LATE_LOADERS``), which rule (b) of ``tests/test_import_graph.py`` names.
DEFERRED = frozenset({"FreeCAD", "FreeCADGui", "Part", "PySide", "matplotlib"})


def _workbench() -> dict[str, object]:
    return {name: path for name, path in modules().items() if name == PACKAGE or name.startswith(PACKAGE + ".")}


def test_every_module_is_on_one_side():
    """A new module of the workbench says which side it is on (``tests/test_import_graph.py``)."""
    names = set(_workbench())
    assert not FREECAD_GUI_SIDE & FREECAD_APP_SIDE
    both = FREECAD_GUI_SIDE | FREECAD_APP_SIDE
    assert names == both, f"not classified: {sorted(names - both)}; gone: {sorted(both - names)}"


def test_app_side_loads_no_module_by_name():
    """No App-side module loads a module by a computed name (``importlib``, ``__import__``) that the
    check of its imports could not see."""
    offenders = [f"{_where(imp)} imports {imp.target}" for imp in all_imports()
                 if imp.module in FREECAD_APP_SIDE and imp.target.split(".")[0] == "importlib"]
    for name in FREECAD_APP_SIDE:
        path = modules()[name]
        offenders += [f"{path.name}:{n.lineno} calls __import__" for n in ast.walk(ast.parse(path.read_text("utf-8")))
                      if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "__import__"]
    assert not offenders, "\n".join(offenders)


def test_app_side_loads_the_gui_libraries_only_inside_functions():
    """An App-side module imports in ``freecadcmd``: FreeCADGui and PySide only inside the
    function that shows a dialog."""
    offenders = [f"{_where(imp)} imports {imp.target} at its top level" for imp in all_imports()
                 if imp.module in FREECAD_APP_SIDE and imp.place != "function"
                 and imp.target.split(".")[0] in GUI_LIBRARIES]
    assert not offenders, "\n".join(offenders)


def test_imports_inside_functions_only_defer_freecad_the_gui_or_matplotlib():
    """An import inside a function of the workbench defers FreeCAD, the GUI or matplotlib (never
    OCP, cadquery or the other deferrable dependencies of the rest of the tree); the package's own
    modules and the generators are imported at the top (no cycle needs hiding: the App side never
    imports the Gui side), but for the late loaders rule (b) names."""
    offenders = [f"{_where(imp)} imports {imp.target} inside a function" for imp in all_imports()
                 if imp.module in _workbench() and imp.place != "module"
                 and imp.target.split(".")[0] not in DEFERRED
                 and not imp.target.startswith(LATE_LOADERS.get(imp.module, ("\0",)))
                 and not (imp.scope == "__getattr__" and imp.target.startswith(imp.module + "."))
                 and (imp.module, imp.scope) not in HOOKS]
    assert not offenders, "\n".join(offenders)
