"""The STEP file of a cam, written atomically: the kernel's STEP writer
(:func:`cam_workbench.kernel.step.write_step`) into a temporary file that replaces the target."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.spec import CamSpec
from cam_workbench.kernel.step import write_step

from .atomic import atomic_path


def export_step(shape: Any, path: str | os.PathLike[str], units: str = "mm", product_name: str = "cam") -> Path:
    """Write ``shape`` as STEP (AP214) to ``path`` atomically, declaring ``units`` ("mm"/"in") and
    naming the product ``product_name`` (the body's name)."""
    with atomic_path(path) as tmp:
        write_step(shape, tmp, units, product_name)
    return Path(path)


def product_name(spec: CamSpec) -> str:
    """The STEP product name of ``spec``'s cam: its body's name ("Plate cam", "Groove cam",
    "Conjugate cam pair", "Cylindrical cam")."""
    return body_of(spec).title
