"""Many cams on one camshaft, from Python (issue 24; docs/machine.md).

    from cam_workbench import Machine
    m = Machine("docs/examples/machine_three_cams.toml")     # or Machine.example("three_cams"), or a dict
    r = m.analyse()                  # timing, tools, torques, flywheel, clearances (no solids): MachineResult
    report = m.build("out/machine")  # every cam as `build` builds it in out/machine/<name>/, and
                                     # machine.json, machine.html, timing.svg, torque.svg (and .png
                                     # with CairoSVG), machine.gif (animation="gif" | "mp4" | "none")

Every cam goes through the one pipeline (:func:`cam_workbench.pipeline.run_pipeline`,
:func:`~cam_workbench.pipeline.write_outputs`), so its folder is what ``cam-workbench build``
writes for its spec.  The whole output folder is one set (:class:`~cam_workbench.exporters.atomic.OutputSet`):
everything or nothing is written, and the folder follows the output rule
(:mod:`cam_workbench.exporters.output_rule`: a re-run of the same machine replaces its own set,
another set only with ``replace=True``, a folder holding files of yours never).
"""
from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.chart_png import png_bytes, require_png
from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.machine_animation import DEFAULT_FPS, animation_bytes, require_ffmpeg, require_matplotlib
from cam_workbench.exporters.machine_plots import timing_chart, torque_chart
from cam_workbench.exporters.machine_report import HTML_NAME, JSON_NAME, machine_html, machine_json_text
from cam_workbench.exporters.output_rule import Claim, admit, file_source, script_source, spec_claim, study_digest
from cam_workbench.generators.errors import GeometryError, MissingDependency, SpecError
from cam_workbench.generators.machine import (MachineResult, MachineSpec, analyse_machine, example_machine_dict,
                                              load_machine, machine_from_dict)
from cam_workbench.generators.machine.analysis import check_sweep
from cam_workbench.generators.machine.frames import MachineFrames, machine_frames, turn_angles

from .pipeline import CamOutputs, run_pipeline, write_outputs

#: progress callback: (done, total, what)
Progress = Callable[[int, int, str], None]
#: the figures: key → (SVG file, PNG file); the PNGs only when CairoSVG imports
FIGURES = {"timing": ("timing.svg", "timing.png"), "torque": ("torque.svg", "torque.png")}
#: the animation's formats (``--animation``); "none" writes no animation
ANIMATIONS = ("gif", "mp4", "none")
#: [deg] the animation's step of machine angle: 72 frames over one turn
ANIMATION_STEP_DEG = 5.0


def check_animation(animation: str, required: bool = True) -> str | None:
    """Check ``animation`` ("gif", "mp4" or "none") before any work: what it needs — matplotlib and
    Pillow to draw it, ffmpeg on the PATH for "mp4".  Returns None when it can be written (or is
    "none"); when a dependency is missing and not ``required``, the note why there is no animation.

    Raises:
        SpecError: an unknown value (naming ``--animation``).
        MissingDependency: ``required`` and matplotlib/Pillow or, for "mp4", ffmpeg is missing
            (naming ``--animation gif|mp4``).
    """
    if animation not in ANIMATIONS:
        raise SpecError("--animation", f"is {animation!r}, must be one of {', '.join(ANIMATIONS)}")
    if animation == "none":
        return None
    try:
        require_matplotlib(f"--animation {animation}")
        if animation == "mp4":
            require_ffmpeg()
    except MissingDependency as exc:
        if required:
            raise
        return f"no animation: {exc}"
    return None


def png_note() -> str | None:
    """None when CairoSVG (and the cairo library it loads) imports, so the figures are written as
    PNG too; else the note why only their SVG is."""
    try:
        require_png()
    except MissingDependency as exc:
        return (f"{', '.join(png for _svg, png in FIGURES.values())} not written: PNG figures need CairoSVG and "
                f"the cairo library (pip install 'cam-workbench[png]', and the system's libcairo2); the SVG figures "
                f"are written and shown in machine.html ({exc.__cause__ or exc})")
    return None


@dataclass
class Machine:
    """A machine: its validated spec and the name its outputs record as their source (a machine
    file's resolved path, ``example:NAME`` or ``python:<script>``)."""

    spec: MachineSpec
    source: str

    def __init__(self, machine: str | os.PathLike[str] | Mapping[str, Any] | MachineSpec, source: str | None = None):
        """``machine``: a machine file's path, its TOML structure (spec paths relative to the
        working directory) or a :class:`MachineSpec`.

        Raises:
            SpecError: the machine breaks a rule (naming the field)."""
        if isinstance(machine, MachineSpec):
            self.spec, default = machine, script_source()
        elif isinstance(machine, Mapping):
            self.spec, default = machine_from_dict(machine), script_source()
        else:
            self.spec, default = load_machine(machine), file_source(machine)
        self.source = source or default

    @classmethod
    def example(cls, name: str = "three_cams") -> "Machine":
        """The built-in machine ``name`` (:data:`cam_workbench.generators.machine.MACHINES`)."""
        return cls(example_machine_dict(name), source=f"example:{name}")

    def analyse(self, phase_sweep: str | None = None) -> MachineResult:
        """Timing (each follower's program — the follower's also when a linkage is driven from the
        tool — and each tool's path and motion), torques, the flywheel and the clearances (no solid,
        no file); ``phase_sweep``: a cam's name, whose phase sweep is added.

        Raises:
            SpecError: ``phase_sweep`` names no cam of a clearance pair."""
        return analyse_machine(self.spec, sweep=phase_sweep)

    def claim(self, replace: bool = False, option: str = "folder") -> Claim:
        """The claim of this machine's set on an output folder (its digest: the machine with every
        cam's spec inline)."""
        definition = self.spec.to_dict()
        return Claim("machine", self.source, study_digest(definition), definition, replace, option)

    def build(self, folder: str | os.PathLike[str], *, replace: bool = False, option: str = "folder",
              progress: Progress | None = None, phase_sweep: str | None = None, animation: str = "gif",
              require_animation: bool = False) -> dict[str, Any]:
        """Build every cam into ``folder/<name>/`` as ``build`` does and write the machine's
        outputs into ``folder``; returns machine.json's dict (as written).  ``phase_sweep``: a
        cam's name — machine.json gets the phases of that cam that keep every clearance and its
        shortest cycle.  ``animation``: "gif" (machine.gif), "mp4" (machine.mp4, needs ffmpeg) or
        "none"; a cam that is not drawn (cylindrical, indexing) is left out of it with a note in
        machine.json's ``animation``; a machine with no cam drawn, or without matplotlib, gets no
        animation and a note — or is refused when ``require_animation`` (the CLI: an explicit
        ``--animation``).  The figures are written as SVG, and as PNG when CairoSVG imports
        (machine.json's ``figures`` says which).

        Raises:
            SpecError: ``folder`` or ``animation`` refused (before any work), a cam's spec breaks a
                rule, ``phase_sweep`` names no cam of a clearance pair (naming ``--phase-sweep``),
                or ``require_animation`` and no cam is drawn (naming ``--animation``).
            GeometryError: a cam cannot be made (naming the cam); nothing is written.
            MissingDependency: OCP (the solids) or, with ``require_animation``, matplotlib/Pillow
                or for "mp4" ffmpeg is missing (before any work).
        """
        check_animation(animation, require_animation)
        if phase_sweep is not None:
            check_sweep(self.spec, phase_sweep)
        claim = self.claim(replace, option)
        admit(folder, claim)
        return build_machine(self.spec, folder, claim, self.source, progress=progress, sweep=phase_sweep,
                             animation=animation, require_animation=require_animation)


def _cam_outputs(machine: MachineSpec, progress: Progress | None, total: int) -> list[CamOutputs]:
    """Every cam through the pipeline (design, solid, machining, drawing), naming the cam in an
    error; nothing written."""
    out = []
    for i, cam in enumerate(machine.cams):
        if progress:
            progress(i, total, f"designing {cam.name}")
        try:
            out.append(run_pipeline(cam.spec))
        except SpecError as exc:
            raise SpecError(f"cam[{i}].spec.{exc.field}", exc.rule) from None
        except GeometryError as exc:
            raise GeometryError(exc.kind, f"cam[{i}] ({cam.name}): {exc}", exc.angle_deg, exc.checks) from None
    return out


def _cam_files(outputs: CamOutputs, claim: Claim) -> tuple[dict[str, Any], dict[str, bytes]]:
    """(the cam's report.json dict, its set's files by relative name, its manifest included):
    written by :func:`write_outputs` into a private folder, as ``build`` writes them."""
    with tempfile.TemporaryDirectory(prefix="cam-workbench-machine-") as tmp:
        folder = Path(tmp) / "cam"
        report = write_outputs(outputs, folder, claim)
        files = {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}
    return report, files


def progress_total(machine: MachineSpec, animation: str = "gif") -> int:
    """The steps :func:`build_machine` reports: each cam designed and written, the figures, and each
    animation frame (one turn at :data:`ANIMATION_STEP_DEG`) unless ``animation`` is "none"."""
    frames = 0 if animation == "none" else len(turn_angles(ANIMATION_STEP_DEG))
    return 2 * len(machine.cams) + 1 + frames


@dataclass(frozen=True)
class AnimationPlan:
    """What the animation draws: ``frames`` (None: no animation), the cams ``left_out`` of it (not
    plane cams: they take part in the timing, torque and checks all the same) and ``note``, why
    there is no animation or what it leaves out (None: every cam drawn)."""

    frames: MachineFrames | None
    left_out: tuple[str, ...]
    note: str | None


def _frames(machine: MachineSpec, outputs: list[CamOutputs], animation: str, required: bool) -> AnimationPlan:
    """The animation's frames of the cams that are drawn — plane cams (``design.plane``); every other
    cam is left out with a note.  No frames: "none" asked, matplotlib missing, or no cam drawn (then
    refused when ``required``, naming ``--animation``)."""
    if animation == "none":
        return AnimationPlan(None, (), "not asked for (--animation none)")
    missing = check_animation(animation, required)
    if missing is not None:
        return AnimationPlan(None, (), missing)
    drawn = [i for i, o in enumerate(outputs) if o.design.plane]
    left_out = tuple(machine.cams[i].name for i in range(len(outputs)) if i not in drawn)
    why = "; ".join(f"cam[{i}].spec.cam.body is {o.design.spec.cam.body!r}" for i, o in enumerate(outputs)
                    if i not in drawn)
    if not drawn:
        rule = f"no cam is a plane cam ({why}): the animation draws plane cams"
        if required:
            raise SpecError("--animation", f"{animation} cannot be drawn for this machine: {rule} "
                                           "(--animation none writes the rest)")
        return AnimationPlan(None, left_out, f"no animation: {rule}")
    shown = MachineSpec(machine.machine, tuple(machine.cams[i] for i in drawn))
    frames = machine_frames(shown, [outputs[i].design for i in drawn], turn_angles(ANIMATION_STEP_DEG))
    note = None if not left_out else (
        f"{', '.join(left_out)} left out of the animation ({why}: the animation draws plane cams); "
        f"{'it takes' if len(left_out) == 1 else 'they take'} part in the timing, torque and checks")
    return AnimationPlan(frames, left_out, note)


def build_machine(machine: MachineSpec, folder: str | os.PathLike[str], claim: Claim, source: str, *,
                  progress: Progress | None = None, sweep: str | None = None, animation: str = "gif",
                  require_animation: bool = False) -> dict[str, Any]:
    """The machine's whole output set in ``folder`` (one atomic set: every cam's folder, machine.json,
    machine.html, the figures as SVG — and PNG when CairoSVG imports (:func:`png_note`) —,
    machine.gif or machine.mp4); returns machine.json's dict as written.  ``progress(done, total,
    what)`` reports each cam designed, each cam written, the figures and each animation frame
    (:func:`progress_total`); ``sweep``: the cam whose phase sweep machine.json gets; ``animation``:
    "gif", "mp4" or "none" (cams that are not drawn are left out of it, and a machine with none
    drawn or without matplotlib gets no animation — each with machine.json's ``animation.note`` —
    or SpecError/MissingDependency naming ``--animation`` when ``require_animation``).  Each cam's
    timing, tool and torque use the follower's program its design made (``design.program``)."""
    check_animation(animation, require_animation)
    n = len(machine.cams)
    outputs = _cam_outputs(machine, progress, progress_total(machine, animation))
    plan = _frames(machine, outputs, animation, require_animation)
    frames = plan.frames
    no_png = png_note()
    total = progress_total(machine, animation if frames is not None else "none")
    result = analyse_machine(machine, [o.design.program for o in outputs], sweep=sweep)
    with OutputSet(Path(folder), claim) as o:
        checks = {}
        for i, (cam, out) in enumerate(zip(machine.cams, outputs)):
            if progress:
                progress(n + i, total, f"writing {cam.name}/")
            cam_source = cam.source if cam.source != "inline" else f"{source}#cam[{i}]"
            report, files = _cam_files(out, spec_claim(cam.spec, "machine", cam_source, replace=True))
            checks[cam.name] = report.get("checks") or {}
            for name, data in files.items():
                o.add_bytes(f"{cam.name}/{name}", data)
        if progress:
            progress(2 * n, total, "timing diagram, torque, report")
        summary = result.summary(checks)
        files_entry: dict[str, Any] = {"machine_json": JSON_NAME, "machine_html": HTML_NAME,
                                       "cams": {c.name: c.name + "/" for c in machine.cams}}
        for key, (svg_name, png_name) in FIGURES.items():
            files_entry[f"{key}_svg"] = svg_name
            if no_png is None:
                files_entry[f"{key}_png"] = png_name
        summary["figures"] = {"formats": ["svg"] if no_png else ["svg", "png"], "note": no_png}
        if frames is not None:
            anim_name = f"machine.{animation}"
            files_entry["animation"] = anim_name
            summary["animation"] = {"file": anim_name, "format": animation, "frames": len(frames),
                                    "step_deg": ANIMATION_STEP_DEG, "fps": DEFAULT_FPS, "note": plan.note,
                                    "left_out": list(plan.left_out)}
            done = 2 * n + 1

            def frame_progress(i: int, _n: int, what: str) -> None:
                if progress:
                    progress(done + i, total, f"animation {what}")

            o.add_bytes(anim_name, animation_bytes(frames, animation, fps=DEFAULT_FPS, progress=frame_progress))
        else:
            summary["animation"] = {"file": None, "format": animation, "frames": 0, "step_deg": ANIMATION_STEP_DEG,
                                    "fps": DEFAULT_FPS, "note": plan.note, "left_out": list(plan.left_out)}
        report = json.loads(machine_json_text(summary, files_entry))
        figures = {"timing": svg(timing_chart(result, report), "timing"),
                   "torque": svg(torque_chart(result, report), "torque")}
        for key, (svg_name, png_name) in FIGURES.items():
            o.add_text(svg_name, figures[key])
            if no_png is None:
                o.add_bytes(png_name, png_bytes(figures[key]))
        o.add_text(JSON_NAME, machine_json_text(summary, files_entry))
        o.add_text(HTML_NAME, machine_html(report, figures))
    if progress:
        progress(total, total, "done")
    return report


__all__ = ["ANIMATIONS", "ANIMATION_STEP_DEG", "AnimationPlan", "FIGURES", "Machine", "build_machine",
           "check_animation", "png_note", "progress_total"]
