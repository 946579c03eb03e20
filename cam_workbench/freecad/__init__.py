"""The FreeCAD workbench: a parametric ``Cam`` feature of every body, its commands and task panels.

Runs inside FreeCAD's own Python (Debian's FreeCAD 0.20: Python 3.11, numpy 1.24,
scipy 1.10; FreeCAD 1.x).  It builds shapes with FreeCAD's ``Part`` module and never
imports OCP, cadquery or build123d (two OCCT builds in one process crash).

Modules (each imported only when needed, so FreeCAD's start-up stays cheap):

- :mod:`.properties` — spec fields ↔ FreeCAD properties, generated from the spec declarations.
- :mod:`.part_build` — neutral NURBS data → ``Part`` edges, faces and the cam solid.
- :mod:`.feature` — the ``Cam`` feature, its reference geometry and :func:`create`.
- :mod:`.motion_editor`, :mod:`.check_design`, :mod:`.plots`, :mod:`.step_export`,
  :mod:`.spec_io` — what the commands do (each usable headless; Qt only in the dialogs).
- :mod:`.view_providers`, :mod:`.commands`, the panels and dialogs (:mod:`.motion_editor`,
  :mod:`.optimiser_panel`, :mod:`.export_dialog`, :mod:`.qt_compat`) and :mod:`.spec_io_gui` — the
  GUI side; ``mod/InitGui.py`` defines the workbench itself (FreeCAD executes it at start-up,
  so it imports nothing of ours).  The App side (every other module) imports no Gui-side
  module: a new feature gets its view provider through :mod:`.view_hook`, where the GUI
  registers it (``tests/test_freecad_layering.py``).
- :mod:`.install` — registering the workbench in a user's FreeCAD ``Mod`` folder (CLI side).

Headless use (``freecadcmd``)::

    from cam_workbench.freecad.feature import create
    cam = create(doc, "cam.toml")      # or a CamSpec, a dict, None for the default
    doc.recompute(); cam.Shape.Volume
"""
