"""``Cam``: the parametric cam a CadQuery / build123d user touches, of every body — plate,
groove, conjugate, cylindrical (``PlateCam`` is the same class, the name it had before the bodies).

    >>> from cam_workbench import Cam
    >>> cam = Cam("cam.toml")                 # or Cam() for the built-in default
    >>> cam.solid()                           # cadquery.Solid
    >>> cam.workplane()                       # cadquery.Workplane
    >>> cam.part()                            # build123d.Part
    >>> cam.export_step("cam.step")

Every public member serves every body, or refuses with
:class:`~cam_workbench.generators.errors.NotAvailable` naming the body and what to use instead (a
cylindrical cam has no plane pitch curve or profile: :meth:`Cam.pitch_edge`, :meth:`Cam.profile_edge`);
docs/python.md tables which.  In Jupyter a cam shows its picture (:meth:`Cam._repr_svg_`).

The geometry is designed once (``cam_workbench.generators.design_cam``) and the B-rep built once,
lazily; CadQuery and build123d are imported only when their objects are asked for, and each is
an extra of the project (``pip install "cam-workbench[cadquery]"`` / ``[build123d]``): without
it, the method that needs it raises :class:`~cam_workbench.generators.errors.MissingDependency` (an
ImportError) naming the extra.  The solid, STEP and the report need OCP, which either extra
brings (or ``[ocp]`` alone).
"""
from __future__ import annotations

import os
from functools import cached_property
from pathlib import Path
from typing import Any, Mapping

from cam_workbench.exporters import chart_svg, plots
from cam_workbench.exporters.atomic import atomic_path
from cam_workbench.exporters.ecam import ecam_table
from cam_workbench.exporters.output_rule import admit, file_source, script_source, spec_claim
from cam_workbench.exporters.step import export_step, product_name
from cam_workbench.generators.cam_design import CamDesign, design_cam
from cam_workbench.generators.dynamics import analyse_dynamics
from cam_workbench.generators.errors import GeometryError, NotAvailable
from cam_workbench.generators.spec import CamSpec, default_spec, load_spec
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.studies.remedies import with_remedy

from .extras import import_build123d, import_cadquery
from .kernel import ocp as ocp_compat, solids as occ_build
from .pipeline import drawing_document, run_pipeline, write_outputs


class Cam:
    """A cam of any body (``cam.body``: plate, groove, conjugate, cylindrical) built from a spec.

    Args:
        spec: a :class:`CamSpec`, a path to a TOML spec, TOML text, a dict in the spec's
            structure, or None for the built-in default (example "default": the paper's motion
            program on a 40 mm base radius with an 8 mm roller).
        **changes: dotted-path overrides applied to the spec, e.g.
            ``Cam(**{"cam.base_radius": 30, "follower.roller_radius": 6})``.

    Attributes:
        source: the cam's source, recorded in the manifest of the folders :meth:`export` writes
            (a later export of the same source may replace the set there): the spec file's
            resolved path, ``example:NAME``, else the running script (``python:<path>``, or
            ``python`` in an interactive session).

    Raises:
        SpecError: bad input (the message names the field and the rule).
        GeometryError: the cam cannot be made (undercut, self-intersection, bore), with the cam angle.

    A member the cam's body does not have raises :class:`NotAvailable` naming the body and what
    to use instead (docs/python.md tables them); a member whose library is missing raises
    :class:`~cam_workbench.generators.errors.MissingDependency` naming the extra.
    """

    def __init__(self, spec: CamSpec | str | os.PathLike[str] | Mapping[str, Any] | None = None,
                 **changes: Any):
        self.source: str = script_source()
        if spec is None:
            spec = default_spec()
            self.source = "example:default"
        elif not isinstance(spec, CamSpec):
            if isinstance(spec, os.PathLike) or (isinstance(spec, str) and "\n" not in spec):
                self.source = file_source(spec)       # a path (load_spec reads a str without newlines as one)
            spec = load_spec(spec)  # type: ignore[arg-type]
        if changes:
            spec = spec.replace(**changes)
        self.spec: CamSpec = spec
        try:
            self.design: CamDesign = design_cam(spec)
        except GeometryError as exc:            # with the change that would make it
            raise with_remedy(spec, exc) from None
        self._outputs: Any = None

    @classmethod
    def example(cls, name: str = "default", **changes: Any) -> "Cam":
        """A built-in example cam by name (the CLI's ``--example``): "default", "paper",
        "oscillating", "flat", "packaging", "groove", "conjugate", "cylindrical",
        "cylindrical_oscillating", "parallel_indexer", "barrel_indexer" or "globoidal_indexer" (``cam_workbench.generators.spec.examples.DESCRIPTIONS``
        says what each is; docs/spec.md lists them)."""
        cam = cls(example_spec(name), **changes)
        cam.source = f"example:{name}"
        return cam

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> "Cam":
        """Load a spec file."""
        return cls(Path(path))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "Cam":
        """A cam from a dict in the spec's structure (as TOML reads it)."""
        return cls(data)

    # ---- B-rep ------------------------------------------------------------------
    @cached_property
    def shape(self) -> Any:
        """The cam as an OCP ``TopoDS_Solid`` (built once; needs OCP, which every extra brings)."""
        ocp_compat.require("Cam's solid")
        return occ_build.cam_solid(self.design)

    def solid(self) -> Any:
        """The cam as a ``cadquery.Solid`` (needs the ``[cadquery]`` extra)."""
        cq = import_cadquery("Cam.solid()")

        return cq.Solid(self.shape)

    def workplane(self) -> Any:
        """A ``cadquery.Workplane`` on the XY plane holding the cam solid (needs the
        ``[cadquery]`` extra)."""
        cq = import_cadquery("Cam.workplane()")

        return cq.Workplane("XY").newObject([self.solid()])

    def part(self) -> Any:
        """The cam as a ``build123d.Part`` (needs the ``[build123d]`` extra)."""
        bd = import_build123d("Cam.part()")

        return bd.Part([bd.Solid(self.shape)])

    def profile_edge(self) -> Any:
        """The exact profile as a ``cadquery.Edge`` in the XY plane, counter-clockwise (for
        sketches and further modelling; needs the ``[cadquery]`` extra): a plate cam's outline, a
        groove cam's inner wall, a conjugate pair's first cam.

        Raises:
            NotAvailable: the body has no plane profile (a cylindrical cam), saying what to use instead.
        """
        self._refuse_without_plane_curves("profile_edge()", "profile")
        cq = import_cadquery("Cam.profile_edge()")

        return cq.Edge(occ_build.nurbs_to_edge(self.design.profile_ccw()))

    def pitch_edge(self) -> Any:
        """The pitch curve (a flat face's contact curve; a conjugate pair's first) as a
        ``cadquery.Edge`` in the XY plane (reference geometry; needs the ``[cadquery]`` extra).

        Raises:
            NotAvailable: the body has no plane pitch curve (a cylindrical cam), saying what to use instead.
        """
        self._refuse_without_plane_curves("pitch_edge()", "pitch curve")
        cq = import_cadquery("Cam.pitch_edge()")

        return cq.Edge(occ_build.nurbs_to_edge(self.design.pitch_nurbs))

    def _refuse_without_plane_curves(self, member: str, curve: str) -> None:
        """NotAvailable when the design is not a plane cam (its ``plane`` capability), in the
        design's words for what stands for the plane curves."""
        if not self.design.plane:
            raise NotAvailable(f"Cam.{member}: a {self.spec.cam.body} cam has no plane {curve} — "
                               f"{self.design.instead_of_plane_curves}")

    # ---- outputs ----------------------------------------------------------------
    def export_step(self, path: str | os.PathLike[str]) -> Path:
        """Write the solid as STEP in the spec's units, atomically."""
        return export_step(self.step_shape, path, self.spec.units, product_name(self.spec))

    @cached_property
    def step_shape(self) -> Any:
        """The solid written to STEP: :attr:`shape`, except for ``pitch.representation =
        "bspline"``, whose kernel solid has exact offset curves that OCCT's STEP writer cannot
        write — there the profile is the fitted offset B-spline (its error is in the report)."""
        if self.design.bspline is None:
            return self.shape
        return occ_build.cam_solid(self.design, exact_offset=False)

    def export_dxf(self, path: str | os.PathLike[str]) -> Path:
        """Write the manufacturing drawing (DXF, as the spec's [drawing] section says; the body's
        own views — a cylindrical cam's developed, side and end views), atomically."""
        doc, _ = drawing_document(self.design)
        with atomic_path(path) as tmp:
            doc.saveas(str(tmp))
        return Path(path)

    def outputs(self) -> Any:
        """Every output of the cam, computed by the one pipeline ``cam-workbench build`` runs
        (:class:`cam_workbench.pipeline.CamOutputs`; nothing written)."""
        if self._outputs is None:
            self._outputs = run_pipeline(self.spec, design=self.design)
        return self._outputs

    def report(self) -> dict[str, Any]:
        """The numbers of ``report.json`` (without ``files``), as ``cam-workbench build`` writes them."""
        return self.outputs().summary

    def export(self, folder: str | os.PathLike[str], *, replace: bool = False, plots: bool = False) -> dict[str, Any]:
        """Write everything ``cam-workbench build`` writes (cam.step, cam.dxf, cam.nc,
        commands.csv, report.json, report.html; with ``plots`` the figures as PNG files, as
        ``--plots``) into ``folder`` as one set; returns the report as written.  ``folder`` may be absent or empty, or hold a set of the same spec (its
        other files stay) or of the same :attr:`source` that this export replaces file for file;
        ``replace=True`` replaces any cam-workbench set (docs/python.md).

        Raises:
            MissingDependency: ``plots`` without CairoSVG (nothing written).
            SpecError: ``folder`` refused — files that are not cam-workbench output (always),
                another cam's set, or a set this export would only partly replace; nothing written.
        """
        claim = spec_claim(self.spec, "Cam.export", self.source, replace=replace, option="folder")
        admit(folder, claim)                    # before the pipeline runs
        return write_outputs(self.outputs(), folder, claim, plots=plots)

    def checks(self) -> dict[str, Any]:
        """report.json's ``checks`` section (the numbers ``cam-workbench check`` prints), without
        building the solid; for every body, the cylindrical cam's own checks included."""
        return run_pipeline(self.spec, solid=False, machining=False, drawing=False, design=self.design,
                            dynamics=False).summary["checks"]

    def dynamics(self, speed_rpm: float | None = None, *, sweep: bool | None = None, **fields: Any) -> Any:
        """The follower train at speed (docs/dynamics.md): a
        :class:`cam_workbench.generators.dynamics.DynamicsResult` whose ``summary()`` is report.json's ``dynamics``
        section.  ``fields`` set ``[dynamics]`` fields by name, e.g. ``stiffness=2000``,
        ``damping_ratio=0.08``; ``speed_rpm`` the cam speed; ``sweep=False`` skips the jump-speed sweep.

        Raises:
            SpecError: the train lacks its data (naming the field).
        """
        spec = self.spec.replace(**{f"dynamics.{k}": v for k, v in fields.items()}) if fields else self.spec
        return analyse_dynamics(spec, self.design.program, speed_rpm=speed_rpm, sweep=sweep,
                                follower=self.design.follower)

    def ecam(self, format: str | None = None, path: str | os.PathLike[str] | None = None, **options: Any) -> Any:
        """The electronic-cam table of the cam's motion (docs/ecam.md): an
        :class:`cam_workbench.exporters.ecam.EcamTable` (its ``text``, ``points``, ``deviation``), written
        atomically to ``path`` when given.  ``format``: "csv", "codesys", "beckhoff" or "lenze";
        ``options``: ``table``, ``step``, ``boundaries``, ``name`` (default: the spec's ``[ecam]``)."""
        table = ecam_table(self.spec, format, program=self.design.program, **options)
        if path is not None:
            table.write(path)
        return table

    @property
    def area(self) -> float:
        """Area of the top face [length²], exact: Green's theorem on the body's loops (a plate cam's
        profile minus bore, keyway and holes; a groove cam's disc minus the groove; a cylindrical
        cam's end face at z = its length).  A barrel or globoidal indexer refuses it (NotAvailable:
        its end faces cut fitted flank surfaces)."""
        return self.design.area

    @property
    def volume(self) -> float:
        """The body's exact volume [length³] (its loops × heights; a cylindrical cam's groove in
        closed form); a barrel or globoidal indexer's is not exact: its core in closed form and its
        rib integrated on a grid of the exact envelope (the error estimate in report.json
        ``body.volume``)."""
        return self.design.volume

    def is_valid(self) -> bool:
        """OCCT's BRepCheck on the solid."""
        return occ_build.is_valid(self.shape)

    def __repr__(self) -> str:
        """The body, the follower and the numbers that identify the cam (``design.label()``), e.g.
        ``Cam(plate cam, lengths in mm: translating roller r = 8, offset e = 0; R_b = 40, thickness 10;
        PH quintic pitch curve, M = 60)``."""
        return f"Cam({self.design.label()})"

    def _repr_svg_(self) -> str | None:
        """The cam's picture for Jupyter (SVG text; :func:`cam_workbench.exporters.plots.picture`:
        the cam and its follower beside the motion, or a cylindrical cam's cylinder beside its
        developed view); None for a design no figure draws (Jupyter then shows the repr)."""
        chart = plots.picture(self.design)
        return None if chart is None else chart_svg.svg(chart, "cam")


#: the name of :class:`Cam` before it served every body (kept: scripts that use it keep working)
PlateCam = Cam


def plate_cam(spec: CamSpec | str | os.PathLike[str] | Mapping[str, Any] | None = None,
              **changes: Any) -> Any:
    """A ``cadquery.Workplane`` holding the cam solid: ``plate_cam("cam.toml").faces(">Z")…``
    (needs the ``[cadquery]`` extra)."""
    import_cadquery("plate_cam()")
    return Cam(spec, **changes).workplane()


def register() -> None:
    """Add ``Workplane.plateCam(spec, **changes)`` to CadQuery (explicit opt-in), which places
    the cam on the current workplane's origin and orientation (needs the ``[cadquery]`` extra)."""
    cq = import_cadquery("cam_workbench.register() (Workplane.plateCam)")

    def _plate_cam(self: Any, spec: Any = None, **changes: Any) -> Any:
        solid = Cam(spec, **changes).solid()
        placed = solid.moved(self.plane.location)
        return self.newObject([placed])

    cq.Workplane.plateCam = _plate_cam  # type: ignore[attr-defined]
