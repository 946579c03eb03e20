"""The optional CAD libraries, each brought by an extra of cam-workbench (docs/install.md).

``cadquery`` and ``build123d`` are not requirements of the project: the core (``generators``,
``exporters``, the command line) needs neither, and a CadQuery user must not get build123d's OCP
build, nor a build123d user CadQuery's.  The functions that hand out CadQuery or build123d
objects import them through :func:`import_cadquery` / :func:`import_build123d`, which say which
extra to install when the library is missing, and what is wrong when it is installed but broken.
"""
from __future__ import annotations

import importlib
from types import ModuleType

from cam_workbench.generators.errors import MissingDependency

from .kernel.ocp import two_distributions_note

#: library module → (its name for people, the extra that brings it)
EXTRAS = {"cadquery": ("CadQuery", "cadquery"), "build123d": ("build123d", "build123d")}


def _import(module: str, what: str) -> ModuleType:
    title, extra = EXTRAS[module]
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name != module:
            raise _broken(title, what, exc) from exc
        raise MissingDependency(f'{what} needs {title}, which is not installed: '
                                f'pip install "cam-workbench[{extra}]"') from exc
    except ImportError as exc:
        raise _broken(title, what, exc) from exc


def _broken(title: str, what: str, exc: BaseException) -> MissingDependency:
    return MissingDependency(f"{what} needs {title}, which is installed but fails to import "
                             f"({type(exc).__name__}: {exc}){two_distributions_note()}")


def import_cadquery(what: str) -> ModuleType:
    """``import cadquery`` for ``what`` (e.g. "PlateCam.workplane()"), or MissingDependency
    naming the ``[cadquery]`` extra."""
    return _import("cadquery", what)


def import_build123d(what: str) -> ModuleType:
    """``import build123d`` for ``what`` (e.g. "PlateCam.part()"), or MissingDependency naming
    the ``[build123d]`` extra."""
    return _import("build123d", what)
