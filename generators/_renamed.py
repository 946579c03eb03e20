"""The flat module names of generators before the stage layout (``generators.design_checks``
→ ``generators.checks.design``, …), kept importable for one release: importing an old name
gives the very module object of the new one (same state, so patching either patches both)."""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys

#: old module (under generators) → new module
RENAMED = {
    "params": "spec.params", "spec_doc": "spec.reference", "examples": "spec.examples",
    "laws": "motion.laws", "bspline_law": "motion.bspline_law",
    "follower": "followers.translating",
    "ph_spline": "curves.ph_spline", "bezier": "curves.bezier", "banded": "curves.banded",
    "extrema": "curves.extrema", "nurbs": "curves.nurbs", "offsets": "curves.offsets", "approx": "curves.approx",
    "pitch_bspline": "pitch.bspline", "follower_line": "pitch.contact",
    "geometry_checks": "checks.buildability", "design_checks": "checks.design", "cam_area": "checks.areas",
    "claims": "checks.claims",
    "interpolator": "machining.interpolator", "toolpath": "machining.toolpath",
    "cutting_time": "machining.cutting_time",
}
# (generators.spec, .motion, .pitch and .machining are now packages that re-export their
# old module: generators.spec.model, .motion.program, .pitch.ph, .machining.plan)


class _Alias(importlib.abc.Loader):
    def __init__(self, target: str):
        self.target = target

    def create_module(self, spec):  # noqa: D102
        module = importlib.import_module(self.target)
        self.spec = module.__spec__
        return module

    def exec_module(self, module):  # noqa: D102
        # the import system has just set the alias's spec on the module: give it back its own,
        # else __package__ != __spec__.parent (a DeprecationWarning on its relative imports
        # since Python 3.12, seen with FreeCAD 1.1's Python 3.14) and reloads use the alias
        module.__spec__ = self.spec


class _RenamedFinder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path=None, target=None):  # noqa: D102
        pkg, _, name = fullname.rpartition(".")
        if pkg != "generators" or name not in RENAMED:
            return None
        new = f"generators.{RENAMED[name]}"
        return importlib.machinery.ModuleSpec(fullname, _Alias(new), origin=new)


def install() -> None:
    """Make the old names importable (idempotent)."""
    if not any(isinstance(f, _RenamedFinder) for f in sys.meta_path):
        sys.meta_path.append(_RenamedFinder())
