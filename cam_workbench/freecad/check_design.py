"""Check design: the design checks, their extremes and the buildability of a ``Cam`` feature.

Three parts, all computed inside FreeCAD from ``generators`` (pure numpy/scipy, so FreeCAD's
own Python runs them):

- the **design checks** of ``cam_workbench.generators.checks.design.run_checks`` (thesis Ch. 3: pressure
  angle, separation, oscillation, Hertz contact stress; for knife edges and rollers curvature
  with the undercut factor and the roller envelope, for flat faces the cusp and the face width),
  with the limits and sampling of the feature's ``[checks]``, ``[material]`` and follower load
  properties: value, cam angle, limit, pass/fail — the table ``cam-workbench check`` prints,
  read from the dict that is report.json's ``checks`` section;
- the **extremes** (the thesis' "Maximum Values": force, pressure angle, stress, reduced
  velocity, acceleration and jerk, signed, with their cam angles);
- the **follower dynamics** when the feature's ``DynamicsEnabled`` (spec ``dynamics.enabled``) is on:
  the rows of report.json's ``dynamics`` section (``cam_workbench.generators.dynamics.analyse_dynamics(...).summary()``,
  the function ``cam-workbench dynamics`` and ``build`` call) — whether the follower stays on the cam,
  the jump speed, the contact forces, the displacement error, the camshaft torque and the residual
  vibration; for an indexer (``body`` parallel, barrel or globoidal indexer) the same section is its
  output train's (the output's inertia on the turret shaft: ``dynamics.turret``), and its rows say so —
  the shaft torque, the angle error |φ − ψ|, the torsional deflection, the residual vibration at the
  station — in the section's own units; bad ``[dynamics]`` input (or an input the dynamics need,
  such as ``indexer.output_inertia``) shows the library's message naming the field;
- the **buildability** checks of ``design_cam`` (undercut or cusp, self-intersection, bore,
  which raise with the cam angle), the design numbers — lifts, their errors and derivatives in
  the follower's lift unit (report.json's ``motion.lift_unit``: the arm's degrees for an
  oscillating follower) — and FreeCAD's own verdict on the solid.

A failing check (or a cam that cannot be made) also shows what makes it pass: the remedies of
report.json's ``checks.results[name].remedy`` (``cam_workbench.generators.studies.remedies``), the field named as
its property.

The follower is named by its own label (``Follower.describe()``, report.json's ``follower``
section); which checks and rows exist is read from the results, never from the kind.

:func:`design_report` is headless; :func:`show_report` renders it in a dialog.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.checks.claims import profile_claim
from cam_workbench.generators.checks.design import format_value as fmt_value
from cam_workbench.generators.checks.design import limit_sign, run_checks
from cam_workbench.generators.checks.status import sampling_words
from cam_workbench.generators.dynamics import analyse_dynamics
from cam_workbench.generators.errors import CamError, GeometryError, SpecError
from cam_workbench.generators.kinds import body_of, follower_of, pitch_named
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.studies.remedies import add_remedies, refusal_remedies

from . import properties as props
from .bodies import builder_for


@dataclass(frozen=True)
class CheckRow:
    """One design check (``cam_workbench.generators.checks.design.CheckResult``) as the table shows it."""

    name: str
    description: str
    kind: str                 # "max" or "min"
    value: float | None
    at_deg: float | None
    limit: float | None
    unit: str
    status: str               # "pass", "fail", "skipped"
    note: str

    def cells(self) -> list[str]:
        """check, value, at cam angle, limit (with its comparison), status, note."""
        op = limit_sign(self.name, self.kind)
        return [self.name.replace("_", " "), fmt_value(self.value, self.unit),
                "—" if self.at_deg is None else f"{self.at_deg:.3f}°",
                "—" if self.limit is None else f"{op} {fmt_value(self.limit, self.unit)}",
                self.status, self.note]


@dataclass(frozen=True)
class DynamicsRow:
    """One row of the Follower dynamics table: a number of report.json's ``dynamics`` section
    (``path``: its keys there, e.g. ``("contact", "min_force")``; ``at_path`` the keys of its cam
    angle) or, with ``path`` None, a line of text (the verdict)."""

    quantity: str
    value: float | None
    unit: str
    at_deg: float | None = None
    status: str = ""               # "pass", "FAIL" or "" (information)
    path: tuple[Any, ...] | None = None
    at_path: tuple[Any, ...] | None = None
    text: str | None = None        # shown instead of the value (the verdict, a note)

    def cells(self) -> list[str]:
        """quantity, value, unit, at cam angle, status."""
        value = self.text if self.text is not None else fmt_number(self.value)
        return [self.quantity, value, self.unit, "—" if self.at_deg is None else f"{self.at_deg:.3f}°", self.status]


def fmt_number(v: float | None) -> str:
    """A dynamics number as the table shows it: six significant digits (report.html's format)."""
    if v is None:
        return "—"
    return f"{v:.6g}"


@dataclass
class DesignReport:
    """Everything Check design shows.  ``rows`` are (group, item, value, status) of the
    buildability checks and design numbers; status "pass", "FAIL" or "" (information)."""

    ok: bool
    error: str | None = None
    rows: list[tuple[str, str, str, str]] = field(default_factory=list)
    checks: list[CheckRow] = field(default_factory=list)
    extremes: list[tuple[str, float, float, str]] = field(default_factory=list)  # name, value, at_deg, unit
    sampling: str = ""
    checks_error: str | None = None
    #: report.json's ``checks`` section these rows were read from (None before the checks ran)
    checks_dict: dict[str, Any] | None = None
    #: report.json's ``follower`` section (``Follower.describe()``; None for a bad spec)
    follower: dict[str, Any] | None = None
    units: str = ""
    #: the feature's dynamics.enabled: the Follower dynamics table is shown
    dynamics_enabled: bool = False
    #: report.json's ``dynamics`` section (None when not enabled or not analysed)
    dynamics_dict: dict[str, Any] | None = None
    dynamics: list[DynamicsRow] = field(default_factory=list)
    #: why the dynamics could not be analysed (the library's message, the field named as the property)
    dynamics_error: str | None = None
    #: the train the dynamics are of: "follower", or an indexer's "output train" (its turret:
    #: ``Body.dynamics_follower(spec).turret``)
    train: str = "follower"
    #: what makes each failing check (or the refusal) pass: one line per check (:func:`remedy_texts`)
    remedies: list[str] = field(default_factory=list)

    @property
    def contact_kept(self) -> bool | None:
        """report.json's ``dynamics.contact.kept`` (None without dynamics)."""
        return None if self.dynamics_dict is None else bool(self.dynamics_dict["contact"]["kept"])

    def dynamics_verdict(self) -> str:
        """The follower stays on the cam / LEAVES the cam at N rpm (or why it was not analysed)."""
        if not self.dynamics_enabled:
            return ""
        if self.dynamics_error is not None:
            return f"{self.train} dynamics not analysed: {self.dynamics_error}"
        d = self.dynamics_dict
        if d is None:
            return ""
        rpm = fmt_number(d["speed_rpm"])
        if is_turret(d):      # form closure: the rollers never leave the cam (docs/indexing.md)
            return f"the rollers hold the turret both ways at {rpm} rpm (output train: no separation)"
        if d["contact"]["kept"]:
            return f"the follower stays on the cam at {rpm} rpm"
        return (f"the follower LEAVES the cam at {rpm} rpm "
                f"({fmt_number(d['contact']['off_cam_deg'])}° of the revolution off the cam)")

    @property
    def dynamics_title(self) -> str:
        """The dynamics tab's title: "Output train dynamics" for an indexer's turret (report.json's
        ``dynamics.turret``), "Follower dynamics" otherwise."""
        turret = is_turret(self.dynamics_dict) if self.dynamics_dict is not None else self.train == "output train"
        return "Output train dynamics" if turret else "Follower dynamics"

    @property
    def follower_text(self) -> str:
        """The follower's label with the spec's length unit, as the report's drawing titles it."""
        if not self.follower:
            return ""
        return f"{self.follower['label']} {self.units}".strip()

    @property
    def failed_checks(self) -> list[str]:
        """report.json's ``checks.failed`` (verbatim)."""
        if self.checks_dict is not None:
            return list(self.checks_dict.get("failed") or [])
        return [c.name for c in self.checks if c.status == "fail"]

    @property
    def buildable(self) -> bool:
        return self.error is None and all(r[3] != "FAIL" for r in self.rows)

    def verdict(self) -> str:
        if self.checks_error:
            return f"not checked: {self.checks_error}"
        parts = []
        if self.failed_checks:
            parts.append("design checks failed: " + ", ".join(n.replace("_", " ") for n in self.failed_checks))
        if self.error:
            parts.append(self.error)
        elif not self.buildable:
            parts.append("buildability check failed")
        if self.dynamics_error is not None or self.contact_kept is False:
            parts.append(self.dynamics_verdict())
        return "; ".join(parts) if parts else "all checks pass"

    def text(self) -> str:
        lines = [self.verdict()]
        if self.follower:
            lines.append(f"  follower: {self.follower_text}")
        if self.checks:
            lines.append(f"  design checks ({self.sampling}):")
            for c in self.checks:
                cells = c.cells()
                lines.append(f"    {cells[0]:<15} {cells[1]:>16} at {cells[2]:>9}  limit {cells[3]:<16} "
                             f"{cells[4]}" + (f" ({cells[5]})" if cells[5] and c.status != "pass" else ""))
        for line in self.remedies:
            lines.append(f"  to pass: {line}")
        if self.extremes:
            lines.append("  extremes: " + "; ".join(f"{n.replace('_', ' ')} {fmt_value(v, u)} at {a:.3f}°"
                                                    for n, v, a, u in self.extremes))
        if self.dynamics_enabled:
            lines.append(f"  {self.dynamics_title.lower()}: {self.dynamics_verdict()}")
            for r in self.dynamics:
                c = r.cells()
                lines.append(f"    {c[0]:<44} {c[1]:>16} {c[2]:<8} at {c[3]:>9}  {c[4]}")
            if self.dynamics_dict is not None:
                lines.append(f"    {steady_state_text(self.dynamics_dict)}")
        for group, item, value, status in self.rows:
            lines.append(f"  {group:<15} {item:<38} {value:<30} {status}")
        return "\n".join(lines)


def design_report(obj: Any, dynamics_progress: Any = None) -> DesignReport:
    """Run the design checks, design the feature's cam (no shape is changed) and, when the
    feature's ``DynamicsEnabled`` is on, analyse the follower dynamics (``dynamics_progress(done,
    total, what)`` follows the jump-speed sweep)."""
    dynamics_error = None
    try:
        spec = props.spec_of(obj)
    except SpecError as exc:
        msg = f"{props.describe_field(exc.field)}: {exc.rule}"
        # a rule of [dynamics], or one the dynamics add (an indexer's indexer.output_inertia): the
        # spec without [dynamics] is valid
        spec = _spec_without_dynamics(obj)
        if spec is None:
            return DesignReport(False, msg, checks_error=msg)
        dynamics_error = msg   # the cam itself is fine: check it, and say why the dynamics are not analysed

    if not body_of(spec).plane:     # a body that designs itself: its own design, checks and rows
        return _own_body_report(obj, spec, dynamics_error, dynamics_progress)
    report = DesignReport(True, follower=follower_of(spec).describe(), units=spec.units)
    _add_checks(report, spec)
    _add_buildability(report, obj, spec)
    report.dynamics_enabled = bool(getattr(obj, "DynamicsEnabled", False))
    if dynamics_error is not None:
        report.dynamics_enabled = True
        report.dynamics_error = dynamics_error
    elif report.dynamics_enabled:
        _add_dynamics(report, spec, dynamics_progress)
    report.ok = (report.checks_error is None and not report.failed_checks and report.buildable
                 and report.dynamics_error is None and report.contact_kept is not False)
    return report


def _own_body_report(obj: Any, spec: Any, dynamics_error: str | None, dynamics_progress: Any = None
                     ) -> DesignReport:
    """Check design of a body that is not a plane cam (it designs itself: a cylindrical cam, the
    three indexers): its design checks are the ``checks`` section of its report.json, its rows the
    body's numbers (:meth:`cam_workbench.freecad.part_build.FreeCADBody.design_rows`) and, with
    ``DynamicsEnabled``, its dynamics section (an indexer's: the output train)."""
    report = DesignReport(True, units=spec.units, train=train_name(spec))
    report.dynamics_enabled = bool(getattr(obj, "DynamicsEnabled", False))
    if dynamics_error is not None:
        report.dynamics_enabled, report.dynamics_error = True, dynamics_error
    try:
        design = design_cam(spec)
    except GeometryError as exc:
        where = f" at cam angle {exc.angle_deg:.2f}°" if exc.angle_deg is not None else ""
        report.error = f"the cam cannot be made ({exc.kind}{where}): {exc}"
        report.checks_error = report.error
        report.rows.append(("Buildability", exc.kind.replace("_", " "), str(exc), "FAIL"))
        report.remedies = remedy_texts(refusal_remedies(spec, exc))
        report.ok = False
        return report
    except CamError as exc:
        report.error = report.checks_error = f"the cam cannot be made: {exc}"
        report.ok = False
        return report
    s = design.summary()
    fol = dict(s["follower"])
    fol.setdefault("pressure_angle_text", s["pressure_angle"]["formula"])
    fol.setdefault("curvature_text", builder_for(design).curvature_text)
    report.follower = fol
    checks = add_remedies(s["checks"], spec)  # report.json's checks section
    report.checks_dict = checks
    report.remedies = remedy_texts(checks["results"])
    report.sampling = sampling_words(checks)
    report.checks = check_rows(checks)
    report.extremes = [(name, float(e["value"]), float(e["at_deg"]), e["unit"])
                       for name, e in checks.get("extremes", {}).items()]
    report.rows += builder_for(design).design_rows(s)
    report.rows += _kernel_rows(obj, design)
    if report.dynamics_enabled and report.dynamics_error is None:
        _add_dynamics(report, spec, dynamics_progress, design)
    report.ok = (not report.failed_checks and report.buildable and report.dynamics_error is None
                 and report.contact_kept is not False)
    return report


def train_name(spec: Any) -> str:
    """What the spec's dynamics are of: an indexer's "output train" (the output's inertia on the
    turret shaft: the body's ``dynamics_train`` is "turret"), else the "follower"."""
    try:
        turret = body_of(spec).dynamics_train == "turret"
    except CamError:
        turret = False
    return "output train" if turret else "follower"


def _spec_without_dynamics(obj: Any) -> Any:
    """The feature's spec without its ``[dynamics]`` (which break a rule), or None when the rest
    breaks one too."""
    data = props.spec_dict(obj)
    data.pop("dynamics", None)
    try:
        return CamSpec.from_dict(data)
    except SpecError:
        return None


def is_turret(d: dict[str, Any]) -> bool:
    """report.json's ``dynamics`` section is an indexer's output train (it has ``turret``)."""
    return d.get("turret") is not None


def dynamics_rows(d: dict[str, Any]) -> list[DynamicsRow]:
    """The rows of the Follower dynamics table from report.json's ``dynamics`` section
    (``DynamicsResult.summary()``): every number is the section's own, with its unit and, where
    the section gives one, its cam angle.  An indexer's section (:func:`is_turret`) is its output
    train's: the "contact force" is the turret shaft's torque, the error the output's angle error
    φ − ψ, and the rows of its ``turret`` subsection follow.  No FreeCAD needed."""
    c, m, e, tq, rpm = d["contact"], d["model"], d["error"], d["torque"], d["speed_rpm"]
    fu, lu, tu = c["unit"], e["unit"], tq["unit"]
    kept = bool(c["kept"])
    turret = is_turret(d)
    if turret:      # form closure: the rollers hold the turret both ways (never "on the cam")
        rows = [DynamicsRow(f"output train at {fmt_number(rpm)} rpm (the analysis speed)", rpm, "rpm",
                            status="pass" if kept else "FAIL", path=("speed_rpm",),
                            text="rollers hold the turret both ways" if kept else "LEAVES the cam")]
    else:
        rows = [DynamicsRow(f"follower at {fmt_number(rpm)} rpm (the analysis speed)", rpm, "rpm",
                            status="pass" if kept else "FAIL", path=("speed_rpm",),
                            text="stays on the cam" if kept else "LEAVES the cam")]
    jp = d.get("jump_speed")
    if jp is not None:
        if jp["rpm"] is not None:
            rows.append(DynamicsRow("jump speed (contact first lost)", jp["rpm"], "rpm",
                                    status="pass" if jp["rpm"] > rpm else "FAIL", path=("jump_speed", "rpm")))
            rows.append(DynamicsRow("jump speed / analysis speed", jp["ratio_to_speed"], "",
                                    path=("jump_speed", "ratio_to_speed")))
        else:
            rows.append(DynamicsRow("jump speed (contact first lost)", None, "rpm", path=("jump_speed", "rpm"),
                                    text=f"not found: {jp['note']}"))
        if jp["rigid_rpm"] is not None:
            rows.append(DynamicsRow("jump speed of the rigid follower", jp["rigid_rpm"], "rpm",
                                    path=("jump_speed", "rigid_rpm")))
    rows.append(DynamicsRow("natural frequency of the train", m["natural_frequency_hz"], "Hz",
                            path=("model", "natural_frequency_hz")))

    def at(quantity: str, section: str, key: str, unit: str, at_key: str, *prefix: Any) -> DynamicsRow:
        src = d[section]
        for p in prefix:
            src = src[p]
        return DynamicsRow(quantity, src[key], unit, src[at_key], path=(section, *prefix, key),
                           at_path=(section, *prefix, at_key))

    load = "shaft torque" if turret else "contact force"
    rows += [
        at(f"smallest {load} (dynamic)", "contact", "min_force", fu, "min_force_at_deg"),
        at(f"largest {load} (dynamic)", "contact", "max_force", fu, "max_force_at_deg"),
        at(f"smallest {load} (rigid)", "contact", "rigid_min_force", fu, "rigid_min_force_at_deg"),
        at(f"largest {load} (rigid)", "contact", "rigid_max_force", fu, "rigid_max_force_at_deg"),
        at("largest angle error |φ − ψ| (output − turret)" if turret else "largest displacement error |q − s|",
           "error", "max", lu, "at_deg"),
        at("largest vibration of the output" if turret else "largest vibration", "error", "max_vibration", lu,
           "vibration_at_deg"),
    ]
    if not kept:
        rows.append(DynamicsRow("off the cam", c["off_cam_deg"], "deg", status="FAIL", path=("contact", "off_cam_deg")))
        rows.append(at("largest gap", "contact", "max_gap", lu, "max_gap_at_deg"))
        if c.get("max_landing_speed") is not None:
            rows.append(DynamicsRow("largest landing speed", c["max_landing_speed"], c["landing_speed_unit"],
                                    path=("contact", "max_landing_speed")))
    for which in ("rigid", "dynamic"):
        rows += [
            at(f"camshaft torque max ({which})", "torque", "max", tu, "max_at_deg", which),
            at(f"camshaft torque min ({which})", "torque", "min", tu, "min_at_deg", which),
            DynamicsRow(f"camshaft torque RMS ({which})", tq[which]["rms"], tu, path=("torque", which, "rms")),
        ]
    rows.append(DynamicsRow("work per revolution (dynamic)", tq["dynamic"]["work_per_revolution"], tu,
                            path=("torque", "dynamic", "work_per_revolution")))
    what = "residual vibration of the output" if turret else "residual vibration"
    for i, r in enumerate(d["residual_vibration"]):
        rows.append(DynamicsRow(f"{what} after motion[{r['after']}] {r['kind']} "
                                f"(in motion[{r['next']}] {r['next_kind']})", r["amplitude"], lu, r["at_deg"],
                                path=("residual_vibration", i, "amplitude"),
                                at_path=("residual_vibration", i, "at_deg")))
    if turret:
        rows += turret_rows(d["turret"])
    return rows


def turret_rows(t: dict[str, Any]) -> list[DynamicsRow]:
    """The rows of report.json's ``dynamics.turret`` (an indexer's output train, the numbers
    ``cam-workbench dynamics`` prints under "indexer output train"), each with its path in the
    ``dynamics`` section and the subsection's own units (s, Hz, deg, arcmin, N·mm)."""
    ae, dfl, sq, rv = t["angle_error"], t["deflection"], t["shaft_torque"], t["residual_vibration"]

    def row(quantity: str, value: Any, unit: str, path: tuple[Any, ...], at_deg: Any = None,
            at_path: tuple[Any, ...] | None = None) -> DynamicsRow:
        return DynamicsRow(quantity, value, unit, at_deg, path=("turret", *path),
                           at_path=None if at_path is None else ("turret", *at_path))

    rows = [
        row("output inertia J (indexer.output_inertia)", t["output_inertia"], t["inertia_unit"], ("output_inertia",)),
        row("turret shaft torsional stiffness k_t", t["torsional_stiffness"], t["stiffness_unit"],
            ("torsional_stiffness",)),
        row("index angle of the input", t["index_angle_deg"], "deg", ("index_angle_deg",)),
        row("index time t_i", t["index_time_s"], "s", ("index_time_s",)),
        row("f_n·t_i (natural frequency × index time)", t["fn_ti"], "", ("fn_ti",)),
        row("largest angle error |φ − ψ|", ae["max_arcmin"], "arcmin", ("angle_error", "max_arcmin"),
            ae["at_deg"], ("angle_error", "at_deg")),
        row("peak torsional deflection |ψ − φ| of the shaft", dfl["max_arcmin"], "arcmin",
            ("deflection", "max_arcmin"), dfl["at_deg"], ("deflection", "at_deg")),
        row("largest twist ψ − φ (turret leads the output)", dfl["max_positive"], dfl["unit"],
            ("deflection", "max_positive"), dfl["max_positive_at_deg"], ("deflection", "max_positive_at_deg")),
        row("most negative twist ψ − φ (output leads the turret)", dfl["max_negative"], dfl["unit"],
            ("deflection", "max_negative"), dfl["max_negative_at_deg"], ("deflection", "max_negative_at_deg")),
        row("peak shaft torque (dynamic)", sq["max"], sq["unit"], ("shaft_torque", "max"), sq["at_deg"],
            ("shaft_torque", "at_deg")),
        row("peak shaft torque (rigid J·ψ̈)", sq["rigid_max"], sq["unit"], ("shaft_torque", "rigid_max"),
            sq["rigid_max_at_deg"], ("shaft_torque", "rigid_max_at_deg")),
        row("dynamic factor of the shaft torque", sq["dynamic_factor"], "", ("shaft_torque", "dynamic_factor")),
        row("residual vibration entering the dwell", rv["amplitude_arcmin"], "arcmin",
            ("residual_vibration", "amplitude_arcmin")),
    ]
    for i, w in enumerate(rv["dwells"]):
        span = f"dwell {fmt_number(w['from_deg'])}°–{fmt_number(w['to_deg'])}°"
        rows += [
            row(f"{span}: vibration amplitude at its start", w["amplitude_at_start_arcmin"], "arcmin",
                ("residual_vibration", "dwells", i, "amplitude_at_start_arcmin")),
            row(f"{span}: vibration amplitude at its end", w["amplitude_at_end_arcmin"], "arcmin",
                ("residual_vibration", "dwells", i, "amplitude_at_end_arcmin")),
            row(f"{span}: largest angle error", w["max_error"], rv["unit"],
                ("residual_vibration", "dwells", i, "max_error"), w["max_error_at_deg"],
                ("residual_vibration", "dwells", i, "max_error_at_deg")),
        ]
    return rows


def steady_state_text(d: dict[str, Any]) -> str:
    """How report.json's ``dynamics`` section was solved (``steady_state``), in words."""
    st = d["steady_state"]
    return ("steady state: " + st["method"] + (f", {st['revolutions']} revolutions" if st["revolutions"] else "")
            + ("" if st["periodic"] else " — NOT periodic yet" + (f" ({st['note']})" if st.get("note") else "")))


def _add_dynamics(report: DesignReport, spec: Any, progress: Any, design: Any = None) -> None:
    """report.json's ``dynamics`` section and its rows; with ``design``, from its motion program and
    dynamics follower (an indexer's turret), as ``cam_workbench.pipeline.dynamics_stage`` (``build``) calls it."""
    try:
        # the function `cam-workbench dynamics` and `build` call: its summary() is report.json's section
        section = analyse_dynamics(spec, None if design is None else design.program, progress=progress,
                                   follower=None if design is None else design.follower).summary()
    except SpecError as exc:
        report.dynamics_error = f"{props.describe_field(exc.field)}: {exc.rule}"
        return
    except CamError as exc:
        report.dynamics_error = str(exc)
        return
    report.dynamics_dict = section
    report.dynamics = dynamics_rows(section)


def check_rows(checks: Any) -> list[CheckRow]:
    """The rows of the design-check table, read from report.json's ``checks`` section
    (``DesignChecks.to_dict()``; a ``DesignChecks`` is turned into that dict first), one per
    entry of ``results`` in its order."""
    d = checks.to_dict() if hasattr(checks, "to_dict") else checks
    return [CheckRow(name, str(r.get("description", "")), str(r.get("kind", "")), r.get("value"),
                     r.get("at_deg"), r.get("limit"), str(r.get("unit", "")), str(r.get("status", "")),
                     str(r.get("note", "")))
            for name, r in d["results"].items()]


def remedy_texts(results: Any) -> list[str]:
    """One line per failing check of report.json's ``checks.results`` (or of a refusal's remedies,
    name → ``{"remedy": …}``): its remedy's own text, each field named as its property
    (``CamBaseRadius (cam.base_radius) = 41.78 mm passes every check …``); the alternatives after "or"."""
    lines = []
    for name, r in results.items():
        rem = r.get("remedy") if isinstance(r, dict) else None
        if not rem:
            continue
        parts = []
        for one in [rem, *(rem.get("alternatives") or [])]:
            text = one["text"]
            for path in one.get("changes") or {}:
                text = text.replace(path, props.describe_field(path), 1)
            parts.append(text)
        lines.append(f"{name.replace('_', ' ')}: " + "; or ".join(parts))
    return lines


def checks_table(checks: Any) -> list[list[str]]:
    """The table Check design shows (one row of :meth:`CheckRow.cells` per check), from
    report.json's ``checks`` section: no FreeCAD needed."""
    return [c.cells() for c in check_rows(checks)]


def _add_checks(report: DesignReport, spec: Any) -> None:
    try:
        checks = add_remedies(run_checks(spec).to_dict(), spec)  # the dict report.json's checks section is
    except CamError as exc:
        report.checks_error = str(exc)
        return
    report.checks_dict = checks
    report.remedies = remedy_texts(checks["results"])
    report.sampling = sampling_words(checks)
    report.checks = check_rows(checks)
    report.extremes = [(name, float(e["value"]), float(e["at_deg"]), e["unit"])
                       for name, e in checks["extremes"].items()]


def _add_buildability(report: DesignReport, obj: Any, spec: Any) -> None:
    try:
        design = design_cam(spec)
    except GeometryError as exc:
        where = f" at cam angle {exc.angle_deg:.2f}°" if exc.angle_deg is not None else ""
        report.error = f"the cam cannot be made ({exc.kind}{where}): {exc}"
        report.rows.append(("Buildability", exc.kind.replace("_", " "), str(exc), "FAIL"))
        failing = set(report.failed_checks)
        report.remedies += remedy_texts({n: {"remedy": r} for n, r in refusal_remedies(spec, exc).items()
                                         if n not in failing})      # a failing check's own is shown already
        return
    except CamError as exc:
        report.error = f"the cam cannot be made: {exc}"
        return
    s = design.summary()
    u = s["units"]
    lu = s["motion"]["lift_unit"]          # the lift's unit: u, or "deg" for an arm's rotation
    fol = s["follower"]
    curve = fol["curve"]                   # "pitch curve", or a flat face's "contact curve"
    group = curve[:1].upper() + curve[1:]
    rows = report.rows
    rows += [
        ("Buildability", "undercut (roller vs. convex curvature)" if fol["design_curve"] == "pitch"
         else "cusp (profile radius of curvature > 0)", "none", "pass"),
        ("Buildability", "profile self-intersection", "none", "pass"),
        ("Buildability", "bore inside the profile",
         f"min profile radius {s['profile']['min_radius']:.4g} {u}", "pass"),
    ]
    p = s["pitch"]
    moved = "rotation" if fol["lift_unit"] == "angle" else "displacement"
    rows += [
        (group, "PH quintic segments M" if pitch_named(p.get("representation", "ph")).exact
         else "B-spline knot spans", str(p["segments"]), ""),
        (group, f"max follower {moved} deviation |s_actual − s|",
         f"{p['max_deviation']:.3g} {lu} at {p['max_deviation_at_deg']:.2f}°",
         "" if p["tolerance"] is None else ("pass" if p["max_deviation"] <= p["tolerance"] else "FAIL")),
        (group, "arc length", f"{p['arc_length']:.6g} {u}", ""),
    ]
    pa = s["pressure_angle"]
    rows += [
        ("Pressure angle", "max |φ| (design)", f"{pa['max_deg']:.3f}° at {pa['at_deg']:.2f}°", ""),
        ("Pressure angle", "max |φ| (as built)",
         f"{pa['as_built']['max_deg']:.3f}° at {pa['as_built']['at_deg']:.2f}°", ""),
    ]
    c = s["curvature"]
    rows += [
        ("Curvature", f"min convex {curve} radius", f"{c['min_pitch_radius']:.4g} {u} at {c['at_deg']:.2f}°", ""),
        ("Curvature", "min convex profile radius", f"{c['min_profile_radius']:.4g} {u}", ""),
        ("Curvature", f"min concave {curve} radius",
         "—" if c["min_concave_pitch_radius"] is None else f"{c['min_concave_pitch_radius']:.4g} {u}", ""),
    ]
    m = s["motion"]
    rows += [
        ("Motion", "max lift", f"{m['max_lift']:.6g} {lu}", ""),
        ("Motion", "max velocity", f"{m['max_velocity']:.6g} {lu}/s", ""),
        ("Motion", "max acceleration", f"{m['max_acceleration']:.6g} {lu}/s²", ""),
        ("Motion", "max jerk", f"{m['max_jerk']:.6g} {lu}/s³", ""),
    ]
    pr = s["profile"]
    claim = profile_claim(s, spec.is_roller, u)
    rows += [
        ("Profile", "NURBS", f"degree {pr['degree']}, {pr['poles']} poles, "
                             f"{'rational' if pr['rational'] else 'polynomial'}", ""),
        ("Profile", "is the", claim.text, ""),
        ("Profile", "max distance from the design-intent profile", f"{pr['max_error']:.3g} {u}", ""),
        ("Profile", "cross-section area", f"{s['area']:.8g} {u}²", ""),
        ("Profile", "volume", f"{s['volume']:.8g} {u}³", ""),
    ]
    rows += _kernel_rows(obj, design)


def _kernel_rows(obj: Any, design: Any) -> list[tuple[str, str, str, str]]:
    """FreeCAD's verdict on the feature's current solid (if it is built from this design)."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not str(getattr(obj, "Status", "")).startswith("ok"):
        return [("FreeCAD solid", "state", "not built from the current properties", "")]
    scale = props.units_scale(obj)
    exact = design.volume * scale**3
    rel = abs(shape.Volume - exact) / exact
    valid = shape.isValid() and len(shape.Solids) == 1
    # the design's volume is exact where the body has an exact top face too (prisms, the cylindrical
    # cam's closed forms); a spatial indexer's is a grid integral of the exact envelope
    of = "exact" if builder_for(design).cross_section_area(design) is not None else "the grid integral"
    rows = [
        ("FreeCAD solid", "valid, one solid", "yes" if valid else "no", "pass" if valid else "FAIL"),
        ("FreeCAD solid", f"kernel volume vs {of}", f"{rel:.2e} relative", ""),
    ]
    rows += builder_for(design).solid_rows(design, shape, scale)
    return rows


# ---- the dialog (GUI only) ------------------------------------------------------------------
_GREEN, _RED, _AMBER = "#1a7f37", "#c62828", "#9a6700"


def _table(name: str, headers: list[str], rows: list[list[str]], status_col: int | tuple[int, ...] | None = None
           ) -> Any:
    """A read-only table; the cells of ``status_col`` (one column or several) coloured by status."""
    from PySide import QtGui  # deferred: PySide (the dialog only: the report is read in any Python)

    status_cols = (status_col,) if isinstance(status_col, int) else tuple(status_col or ())
    table = QtGui.QTableWidget(len(rows), len(headers))
    table.setObjectName(name)
    table.setHorizontalHeaderLabels(headers)
    table.verticalHeader().setVisible(False)
    colours = {"pass": _GREEN, "fail": _RED, "FAIL": _RED, "skipped": _AMBER}
    for r, row in enumerate(rows):
        for c, text in enumerate(row):
            item = QtGui.QTableWidgetItem(text)
            if c in status_cols and text in colours:
                item.setForeground(QtGui.QBrush(QtGui.QColor(colours[text])))
                font = item.font()
                font.setBold(True)
                item.setFont(font)
            table.setItem(r, c, item)
    table.resizeColumnsToContents()
    table.horizontalHeader().setStretchLastSection(True)
    table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
    table.verticalHeader().setDefaultSectionSize(table.fontMetrics().height() + 8)
    return table


def show_report(obj: Any) -> DesignReport:
    """Print the report to the report view and show it in a (non-modal) dialog."""
    import FreeCAD  # deferred: FreeCAD (the dialog only: the report is read in any Python)
    import FreeCADGui  # deferred: FreeCADGui (the GUI's; this module is App side)
    from PySide import QtCore, QtGui  # deferred: PySide (the dialog only)

    if getattr(obj, "DynamicsEnabled", False):
        FreeCAD.Console.PrintMessage(f"{obj.Label}: check design: analysing the dynamics "
                                     "(with the jump-speed sweep, where the follower can leave the cam)…\n")
    QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
    try:
        report = design_report(obj)
    finally:
        QtGui.QApplication.restoreOverrideCursor()
    out = FreeCAD.Console.PrintMessage if report.ok else FreeCAD.Console.PrintWarning
    out(f"{obj.Label}: check design: {report.text()}\n")
    dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
    dlg.setObjectName("CamWorkbenchCheckDesign")
    dlg.setWindowTitle(f"Check design — {obj.Label}")
    layout = QtGui.QVBoxLayout(dlg)
    head = QtGui.QLabel(report.verdict())
    head.setWordWrap(True)
    head.setStyleSheet("font-weight: bold; color: " + (_GREEN if report.ok else _RED))
    layout.addWidget(head)
    if report.follower:
        who = QtGui.QLabel(f"Follower: {report.follower_text}")
        who.setObjectName("follower")
        who.setWordWrap(True)
        who.setToolTip(f"Pressure angle: {report.follower['pressure_angle_text']}; radius of curvature: "
                       f"{report.follower['curvature_text']}")
        layout.addWidget(who)
    tabs = QtGui.QTabWidget()
    checks_page = QtGui.QWidget()
    cl = QtGui.QVBoxLayout(checks_page)
    if report.checks_error:
        cl.addWidget(QtGui.QLabel(f"The design checks could not run: {report.checks_error}"))
    else:
        cl.addWidget(QtGui.QLabel(f"Design checks (thesis Ch. 3), {report.sampling}; limits from the "
                                  "Checks, Material, Follower and Follower load properties:"))
        checks = _table("checks", ["check", "value", "at cam angle", "limit", "status", "note"],
                        [c.cells() for c in report.checks], status_col=4)
        for r, c in enumerate(report.checks):
            checks.item(r, 0).setToolTip(c.description)
        cl.addWidget(checks, 3)
        if report.remedies:
            fixes = QtGui.QLabel("To pass (the nearest change of one property, the others held):\n"
                                 + "\n".join(report.remedies))
            fixes.setObjectName("remedies")
            fixes.setWordWrap(True)
            fixes.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
            cl.addWidget(fixes)
        cl.addWidget(QtGui.QLabel("Extremes (largest magnitude, signed — the thesis' maximum values):"))
        cl.addWidget(_table("extremes", ["quantity", "value", "at cam angle"],
                            [[n.replace("_", " "), fmt_value(v, u), f"{a:.3f}°"]
                             for n, v, a, u in report.extremes]), 2)
    tabs.addTab(checks_page, "Design checks")
    build_page = QtGui.QWidget()
    bl = QtGui.QVBoxLayout(build_page)
    if report.error:
        err = QtGui.QLabel(report.error)
        err.setWordWrap(True)
        err.setStyleSheet(f"color: {_RED}")
        bl.addWidget(err)
        if report.remedies and report.checks_error:       # no checks page to show them on
            fixes = QtGui.QLabel("To make it:\n" + "\n".join(report.remedies))
            fixes.setObjectName("remedies")
            fixes.setWordWrap(True)
            bl.addWidget(fixes)
    bl.addWidget(_table("buildability", ["group", "check / quantity", "value", "status"],
                        [list(r) for r in report.rows], status_col=3))
    tabs.addTab(build_page, "Buildability and geometry")
    if report.dynamics_enabled:
        tabs.addTab(_dynamics_page(report), report.dynamics_title)
    layout.addWidget(tabs)
    close = QtGui.QPushButton("Close")
    close.clicked.connect(dlg.accept)
    layout.addWidget(close)
    dlg.resize(900, 660)
    dlg.setModal(False)
    dlg.show()
    _DIALOGS.append(dlg)
    dlg.finished.connect(lambda *_: _DIALOGS.remove(dlg) if dlg in _DIALOGS else None)
    return report


def _dynamics_page(report: DesignReport) -> Any:
    """The Follower dynamics tab (an indexer's: Output train dynamics): the verdict, then report.json's
    ``dynamics`` numbers."""
    from PySide import QtGui  # deferred: PySide (the dialog only)

    page = QtGui.QWidget()
    page.setObjectName("dynamics_page")
    lay = QtGui.QVBoxLayout(page)
    head = QtGui.QLabel(report.dynamics_verdict())
    head.setObjectName("dynamics_verdict")
    head.setWordWrap(True)
    good = report.dynamics_error is None and report.contact_kept is not False
    head.setStyleSheet("font-weight: bold; color: " + (_GREEN if good else _RED))
    lay.addWidget(head)
    if report.dynamics_dict is not None:
        m = report.dynamics_dict["model"]
        if is_turret(report.dynamics_dict):
            text = (f"The indexer's output train (docs/indexing.md, Dynamics): the output's inertia J "
                    f"{fmt_number(m['mass'])} {m['mass_unit']} on the turret shaft's torsional stiffness k_t "
                    f"{fmt_number(m['stiffness'])} {m['stiffness_unit']}, damping ratio "
                    f"{fmt_number(m['damping_ratio'])}; the rollers hold the turret both ways (no separation, no "
                    "jump speed); the numbers of report.json's dynamics section (cam-workbench dynamics):")
        else:
            text = (f"One-degree-of-freedom follower train (docs/dynamics.md): "
                    f"{'arm inertia' if m['coordinate'] == 'arm angle' else 'mass'} {fmt_number(m['mass'])} "
                    f"{m['mass_unit']}, stiffness {fmt_number(m['stiffness'])} {m['stiffness_unit']}, damping ratio "
                    f"{fmt_number(m['damping_ratio'])}, return spring and preload from the Follower load "
                    "properties; the numbers of report.json's dynamics section (cam-workbench dynamics):")
        about = QtGui.QLabel(text)
        about.setObjectName("dynamics_model")
        about.setWordWrap(True)
        lay.addWidget(about)
        table = _table("dynamics", ["quantity", "value", "unit", "at cam angle", "status"],
                       [r.cells() for r in report.dynamics], status_col=4)
        for r, row in enumerate(report.dynamics):
            if row.path is not None:
                table.item(r, 0).setToolTip("report.json: dynamics." + ".".join(str(k) for k in row.path))
        lay.addWidget(table, 1)
        steady = QtGui.QLabel(steady_state_text(report.dynamics_dict))
        steady.setObjectName("dynamics_steady_state")
        steady.setWordWrap(True)
        lay.addWidget(steady)
    else:
        lay.addStretch(1)
    return page


_DIALOGS: list[Any] = []  # keep non-modal dialogs alive until closed
