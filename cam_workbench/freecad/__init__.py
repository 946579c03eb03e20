"""The FreeCAD workbench: a parametric ``PlateCam`` feature, its commands and task panels.

Runs inside FreeCAD's own Python (Debian's FreeCAD 0.20: Python 3.11, numpy 1.24,
scipy 1.10; FreeCAD 1.x).  It builds shapes with FreeCAD's ``Part`` module and never
imports OCP, cadquery or build123d (two OCCT builds in one process crash).

Modules (each imported only when needed, so FreeCAD's start-up stays cheap):

- :mod:`.properties` — spec fields ↔ FreeCAD properties, generated from the spec declarations.
- :mod:`.part_build` — neutral NURBS data → ``Part`` edges, faces and the cam solid.
- :mod:`.feature` — the ``PlateCam`` feature, its reference geometry and :func:`create`.
- :mod:`.motion_editor`, :mod:`.check_design`, :mod:`.plots`, :mod:`.step_export`,
  :mod:`.spec_io` — what the commands do (each usable headless; Qt only in the dialogs).
- :mod:`.view_providers`, :mod:`.commands` — the GUI side; ``mod/InitGui.py`` defines the
  workbench itself (FreeCAD executes it at start-up, so it imports nothing of ours).
- :mod:`.install` — registering the workbench in a user's FreeCAD ``Mod`` folder (CLI side).

Headless use (``freecadcmd``)::

    from cam_workbench.freecad.feature import create
    cam = create(doc, "cam.toml")      # or a CamSpec, a dict, None for the default
    doc.recompute(); cam.Shape.Volume
"""
