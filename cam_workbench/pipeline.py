"""The one output pipeline: design → solid → summary → machining → drawing → report.

Every entry point that makes files or numbers of a cam — ``build``, ``report``, ``check``,
``optimise``, ``gcode``, ``dxf``, :class:`~cam_workbench.cam.Cam` and the FreeCAD
exports (which run these commands) — goes through :func:`run_pipeline`, so that the numbers
they print or write come from one ``summary`` dict, the one ``report.json`` holds.

Stages (each adds its section to the summary, in this order):

* design — :func:`cam_workbench.generators.cam_design.design_cam` (pitch curve, exact profile, buildability,
  design checks): ``pitch``, ``pressure_angle``, ``curvature``, ``profile``, ``areas``, ``checks``;
* solid — the OCCT solid and the one STEP writes, checked valid: ``solid``;
* machining — the G-code program, the command table, the interpolator: ``interpolator``,
  ``machining``;
* drawing — the DXF document: ``drawing``;
* dynamics — only when asked for (``dynamics.enabled``, ``cam-workbench dynamics``): the follower
  train at speed, ``dynamics``;
* report — report.json, report.html and the plots, written by :func:`write_outputs`.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable


from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.dxf import cam_drawing
from cam_workbench.exporters.machining_outputs import machining_outputs
from cam_workbench.exporters.output_rule import Claim
from cam_workbench.exporters.report_pages import JSON_NAME, ReportPage, add_report_files, report_page
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.exporters.step import product_name
from cam_workbench.generators.cam_design import CamDesign, design_cam
from cam_workbench.generators.dynamics import analyse_dynamics
from cam_workbench.generators.errors import GeometryError
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.linkage import linkage_report
from cam_workbench.generators.studies.remedies import add_remedies

from .kernel import ocp, solids
from .kernel.step import write_step

STEP_NAME = "cam.step"
DXF_NAME = "cam.dxf"


@dataclass
class CamOutputs:
    """What the pipeline made of one spec (nothing written yet).

    Attributes:
        spec: the spec.
        design: the designed cam (generators).
        summary: the numbers of report.json (without ``files``).
        shape: the kernel solid (OCP TopoDS_Shape) or None when the solid stage did not run.
        step_shape: the solid STEP writes (the fitted offset for a B-spline pitch curve).
        machining: G-code, command table and their report sections, or None.
        dxf: (ezdxf document, DxfInfo) or None.
    """

    spec: CamSpec
    design: CamDesign
    summary: dict[str, Any]
    shape: Any = None
    step_shape: Any = None
    machining: Any = None
    dxf: Any = None
    extra: dict[str, Any] = field(default_factory=dict)


def design_stage(spec: CamSpec, progress: Callable[[int, float], None] | None = None) -> CamDesign:
    """The designed cam (raises GeometryError/SpecError for a cam that cannot be made)."""
    return design_cam(spec, progress=progress)


def solid_stage(design: CamDesign) -> tuple[Any, Any, dict[str, Any]]:
    """(kernel solid, STEP solid, the ``solid`` section): OCCT's check of the built solid, and its
    body's check of the solid against the design's numbers (:meth:`~.kernel.solids.KernelBody.verify`).

    Raises:
        GeometryError: OCCT finds the solid invalid or not one solid, or its volume or top face
            disagrees with the design's numbers beyond what its integration allows, or a surface
            body's solid lacks its wall faces (:func:`cam_workbench.generators.checks.solid.check_kernel_solid`).
    """
    ocp.require("the cam's solid")
    shape = solids.cam_solid(design)
    # pitch.representation = "bspline": the kernel solid's profile is OCCT's exact offset curve,
    # which STEP cannot hold; the file gets the fitted offset B-spline (design.profile)
    step_shape = shape if design.bspline is None else solids.cam_solid(design, exact_offset=False)
    checked = {id(s): (solids.is_valid(s), solids.count_solids(s)) for s in (shape, step_shape)}  # once each
    if any(not valid or count != 1 for valid, count in checked.values()):
        raise GeometryError("kernel", "OCCT reports the cam solid as invalid")
    solid: dict[str, Any] = {"valid": checked[id(shape)][0], "solids": checked[id(shape)][1]}
    solid.update(solids.SOLIDS.of(design).verify(design, shape, step_shape))
    return shape, step_shape, solid


def summary_stage(design: CamDesign) -> dict[str, Any]:
    """design.summary() with the spec itself (the part of report.json every entry point shares),
    and each failing check's remedy (:func:`cam_workbench.generators.studies.remedies.add_remedies`)."""
    summary = design.summary()
    summary["spec"] = design.spec.to_dict()
    linkage = linkage_report(design.spec, design.program, summary["checks"])
    if linkage is not None:                  # [linkage]: the tool's motion through it
        summary["linkage"] = linkage
    add_remedies(summary["checks"], design.spec)
    return summary


def machining_stage(design: CamDesign, summary: dict[str, Any]) -> Any:
    """The machining outputs (G-code of ``machining.program``, command table), adding the
    ``interpolator`` and ``machining`` sections to ``summary``."""
    machining = machining_outputs(design, summary=summary)
    summary["interpolator"] = machining.interpolator_summary
    summary["machining"] = machining.machining_summary
    return machining


def drawing_document(design: CamDesign, summary: dict[str, Any] | None = None) -> Any:
    """(ezdxf document, its info) of the cam's drawing, the title block quoting ``summary``
    (``design.summary()`` when None); nothing written."""
    return cam_drawing(design, summary)


def drawing_stage(design: CamDesign, summary: dict[str, Any]) -> Any:
    """(ezdxf document, DxfInfo) of the drawing, adding the ``drawing`` section to ``summary``."""
    doc, info = drawing_document(design, summary)
    summary["drawing"] = info.summary()
    return doc, info


def dynamics_stage(design: CamDesign, summary: dict[str, Any],
                   progress: Callable[[int, int, str], None] | None = None) -> Any:
    """The follower train at speed (:func:`cam_workbench.generators.dynamics.analyse_dynamics`), adding the
    ``dynamics`` section to ``summary``; returns the result (its θ-series, for the figures)."""
    result = analyse_dynamics(design.spec, design.program, progress=progress, follower=design.follower)
    summary["dynamics"] = result.summary()
    return result


def run_pipeline(spec: CamSpec, *, solid: bool = True, machining: bool = True, drawing: bool = True,
                 design: CamDesign | None = None,
                 progress: Callable[[int, float], None] | None = None, dynamics: bool | None = None,
                 dynamics_progress: Callable[[int, int, str], None] | None = None) -> CamOutputs:
    """Run the stages for ``spec`` (nothing is written): design, then optionally the solid,
    the machining and the drawing, each adding its section to the one summary; the dynamics
    when ``dynamics`` (default: the spec's ``dynamics.enabled``)."""
    design = design if design is not None else design_stage(spec, progress)
    summary = summary_stage(design)
    out = CamOutputs(spec=spec, design=design, summary=summary)
    if spec.dynamics.enabled if dynamics is None else dynamics:
        out.extra["dynamics"] = dynamics_stage(design, summary, dynamics_progress)
    if solid:
        out.shape, out.step_shape, summary["solid"] = solid_stage(design)
        if "wall_error" in summary["solid"] and isinstance(summary.get("body"), dict):
            summary["body"]["wall_error"] = summary["solid"]["wall_error"]
    if machining:
        out.machining = machining_stage(design, summary)
    if drawing:
        out.dxf = drawing_stage(design, summary)
    return out


# ---- the report ----------------------------------------------------------------------
def plot_count(outputs: CamOutputs) -> int:
    """How many figures the report of ``outputs`` will draw."""
    return len(_page(outputs).figures)


def _page(outputs: CamOutputs) -> ReportPage:
    return report_page(outputs.design, outputs.summary, outputs.extra.get("dynamics"))


def write_outputs(outputs: CamOutputs, folder: str | Path, claim: Claim, *,
                  extra_texts: dict[str, str] | None = None, report: bool = True,
                  progress: Callable[[str], None] | None = None, plots: bool = False) -> dict[str, Any]:
    """Write what ``outputs`` holds into ``folder`` as one set (all or nothing, as ``claim`` may:
    :mod:`cam_workbench.exporters.output_rule`): cam.step, cam.dxf, the machining files, ``extra_texts``
    (name → text) and, with ``report``, report.json/report.html (and with ``plots`` the figures as
    PNG files).  Returns the report dict (or the summary with ``files`` when ``report`` is False).

    Raises:
        SpecError: the folder is refused (naming ``claim.option``; nothing written).
    """
    files: dict[str, Any] = {}
    extra_texts = extra_texts or {}
    with OutputSet(Path(folder), claim) as o:
        if outputs.step_shape is not None:
            shape, units = outputs.step_shape, outputs.spec.units
            name = product_name(outputs.spec)
            o.add(STEP_NAME, lambda p: write_step(shape, p, units, name))
            files["step"] = STEP_NAME
        if outputs.dxf is not None:
            doc = outputs.dxf[0]
            o.add(DXF_NAME, lambda p: doc.saveas(str(p)))
            files["dxf"] = DXF_NAME
        if outputs.machining is not None:
            outputs.machining.write(o)
            files.update(outputs.machining.files)
        for name, text in extra_texts.items():
            o.add_text(name, text)
            files.setdefault("spec" if name.endswith(".toml") else name, name)
        if report:
            return add_report_files(o, _page(outputs), outputs.summary, files, progress=progress, plots=plots)
        files["report"] = JSON_NAME
        text = report_json_text(outputs.summary, files)
        o.add_text(JSON_NAME, text)
        return json.loads(text)
