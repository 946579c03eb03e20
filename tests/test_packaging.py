"""The wheel's layout, read from pyproject.toml: one top-level package, ``cam_workbench``, whose
subpackages ``generators`` and ``exporters`` are the repository's folders of those names; every
folder with an ``__init__.py`` is listed (a missing one would be left out of the wheel)."""
from __future__ import annotations

import sys

from .conftest import ROOT

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def test_every_package_folder_is_in_the_wheel_under_cam_workbench():
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]
    mapping = {"cam_workbench": "cam_workbench", **conf["package-dir"]}
    assert mapping == {"cam_workbench": "cam_workbench", "cam_workbench.generators": "generators",
                       "cam_workbench.exporters": "exporters"}
    folders = set()
    for name, folder in mapping.items():
        for init in (ROOT / folder).rglob("__init__.py"):
            if "__pycache__" in init.parts or init.parent.name in ("mod", "icons"):
                continue
            rel = init.parent.relative_to(ROOT / folder).parts
            if name == "cam_workbench" and rel[:1] in (("generators",), ("exporters",)):
                continue
            folders.add(".".join((name, *rel)))
    assert sorted(conf["packages"]) == sorted(folders)
    assert {p.split(".")[0] for p in conf["packages"]} == {"cam_workbench"}
