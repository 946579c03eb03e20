"""The sections of report.html, one view each: the HTML of one section from report.json (every
number a :mod:`cam_workbench.exporters.report_cells` cell) and the figures already drawn.
:func:`cam_workbench.exporters.report_html.render_report` assembles them into the page."""
from __future__ import annotations

import html
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from cam_workbench.generators.checks.areas import area_label
from cam_workbench.generators.checks.status import sampling_words
from cam_workbench.generators.checks.claims import checks_verdict, profile_claim
from cam_workbench.generators.checks.design import limit_sign
from cam_workbench.generators.kinds import pitch_of
from cam_workbench.generators.spec.params import params_of, unit_name
from cam_workbench.generators.spec import SECTIONS, CamSpec, to_toml
from cam_workbench.generators.studies.remedies import remedy_line

from .report_cells import format_number, has, num_cell, quantity_table, scalars_table


def _area_rows(report: Mapping[str, Any], u: str) -> list[tuple[str, str, str, None]]:
    """Key-number rows of report.json's design-intent ``areas`` the cam has (the thesis' Eq. 4.21
    area, the areas inside the design curve and the profile), each named as :data:`AREA_LABELS` names it."""
    areas = report.get("areas")
    if not isinstance(areas, Mapping):
        return []
    curve = str(report.get("follower", {}).get("curve", "pitch curve"))
    return [(area_label(k, curve), f"areas.{k}", f"{u}²", None) for k in ("thesis_eq_4_21", "pitch_curve", "profile")
            if isinstance(areas.get(k), (int, float))]


def _objective_note(report: Mapping[str, Any]) -> str:
    """What the optimiser minimised, named as report.json names it (``objective_label``, and the
    path ``objective_key`` where the optimised cam's value is), apart from the cross-section."""
    opt = report["optimise"]
    key = opt.get("objective_key")
    where = f" (report.json <code>{html.escape(str(key))}</code>)" if key else ""
    return (f'<p class="note" id="objective">Objective <b>{html.escape(str(opt.get("objective")))}</b>: '
            f'{html.escape(str(opt.get("objective_label", "")))}{where}; the cam\'s cross-section is report.json '
            "<code>area</code>.</p>")


def checks_section(report: Mapping[str, Any]) -> str:
    """The verdict, one row per check of ``checks.results`` and the extremes table."""
    checks = report["checks"]
    results = checks.get("results") if isinstance(checks.get("results"), Mapping) else {}
    mode = sampling_words(checks)
    out = [_verdict(report),
           f'<p class="note">Sampling: {html.escape(mode)} ({html.escape(str(checks.get("points")))} points). '
           "Limits from the spec's [checks], [material] and follower load.</p>",
           '<table class="checks"><tr><th>check</th><th>value</th><th>rule</th><th>limit</th><th>unit</th>'
           "<th>at cam angle [deg]</th><th>status</th><th>note</th></tr>"]
    for name, r in results.items():
        prefix = f"checks.results.{name}"
        status = str(r.get("status"))
        kind = str(r.get("kind"))
        sign = limit_sign(name, kind) if r.get("limit") is not None else ""
        cls = {"fail": "fail", "pass": "pass", "skipped": "skip"}.get(status, "")
        desc = html.escape(str(r.get("description", "")))
        out.append(
            f'<tr class="check {cls}" data-check="{html.escape(name)}" data-status="{html.escape(status)}">'
            f'<td title="{desc}"><code>{html.escape(name)}</code> <span class="note">({html.escape(kind)}: '
            f"{desc})</span></td>"
            f"{num_cell(report, prefix + '.value')}"
            f'<td class="sign" data-sign="{html.escape(sign)}">{html.escape(sign)}</td>'
            f"{num_cell(report, prefix + '.limit')}"
            f"<td>{html.escape(str(r.get('unit', '')))}</td>"
            f"{num_cell(report, prefix + '.at_deg')}"
            f'<td class="{cls}" data-key="{prefix}.status">{html.escape(status)}</td>'
            f'<td data-key="{prefix}.note">{html.escape(str(r.get("note", "")))}</td></tr>')
    out.append("</table>")
    out.append(_remedies(results))
    ext = checks.get("extremes")
    if isinstance(ext, Mapping) and ext:
        out.append("<h3>Extremes (largest magnitude, signed: the thesis' maximum values)</h3>")
        out.append('<table class="extremes"><tr><th>quantity</th><th>value</th><th>unit</th>'
                   "<th>at cam angle [deg]</th></tr>")
        for name, e in ext.items():
            prefix = f"checks.extremes.{name}"
            at = num_cell(report, prefix + ".at_deg") if "at_deg" in e else "<td></td>"
            out.append(f"<tr><td>{html.escape(name.replace('_', ' '))}</td>{num_cell(report, prefix + '.value')}"
                       f"<td>{html.escape(str(e.get('unit', '')))}</td>{at}</tr>")
        out.append("</table>")
    return "".join(out)


def _remedies(results: Mapping[str, Any]) -> str:
    """What makes each failing check pass (report.json's ``checks.results[name].remedy``, the line
    ``cam-workbench check`` prints under its table)."""
    items = [f'<li data-key="checks.results.{html.escape(name)}.remedy"><code>{html.escape(name)}</code>: '
             f"{html.escape(remedy_line(name, r['remedy'])[len(name) + 2:])}</li>"
             for name, r in results.items() if isinstance(r, Mapping) and isinstance(r.get("remedy"), Mapping)]
    if not items:
        return ""
    return ('<h3>To pass (the nearest change of one field, everything else held)</h3><ul class="remedies">'
            + "".join(items) + "</ul>")


#: report.json motion.segments keys of the solved laws, shown per segment: (key, label, unit kind)
_SEGMENT_DETAILS = (
    ("degree", "polynomial degree", ""), ("conditions", "conditions", ""),
    ("velocity", "cruise velocity", "/rad"), ("start_blend_deg", "start blend", "deg"),
    ("end_blend_deg", "end blend", "deg"), ("points", "table points", ""), ("spans", "knot spans", ""),
    ("order", "B-spline order", ""), ("max_error", "fit: max |s_fit − s_i|", "lift"),
    ("max_error_at_deg", "at cam angle", "deg"), ("rms_error", "fit: rms error", "lift"),
    ("tolerance", "table_tolerance", "lift"),
)


def _segments_table(report: Mapping[str, Any], lu: str) -> str:
    """The motion segments whose laws were solved or fitted (polynomial, constant_velocity, table):
    what they came out as (report.json ``motion.segments``)."""
    segs = report.get("motion", {}).get("segments")
    if not isinstance(segs, list):
        return ""
    rows = []
    for i, seg in enumerate(segs):
        if seg.get("law") not in ("polynomial", "constant_velocity", "table"):
            continue
        for key, label, unit in _SEGMENT_DETAILS:
            if key in seg:
                u = lu if unit == "lift" else (lu + unit if unit.startswith("/") else unit)
                rows.append(f"<tr><td>{i}</td><td>{html.escape(str(seg['law']))}</td><td>{html.escape(label)}</td>"
                            f"{num_cell(report, f'motion.segments.{i}.{key}')}<td>{html.escape(u)}</td></tr>")
        if "coefficients" in seg:
            coef = ", ".join(f"{c:.6g}" for c in seg["coefficients"])
            rows.append(f"<tr><td>{i}</td><td>polynomial</td><td>coefficients a₀ … a_d of s = Σ a_k x^k, "
                        f"x = (θ − θ_start)/span</td><td class=\"coef\">"
                        f"{html.escape(coef)}</td><td>{html.escape(lu)}</td></tr>")
    if not rows:
        return ""
    return ("<h3>Solved and fitted segments</h3>"
            '<table class="segments"><tr><th>#</th><th>law</th><th>quantity</th><th>value</th><th>unit</th></tr>'
            + "".join(rows) + "</table>")


def _laws_table(report: Mapping[str, Any]) -> str:
    """report.json ``motion.segments[i].characteristics`` and ``.vdi2143``: per rise or return its
    law's C_v, C_a, C_j, C_v·C_a and its VDI 2143 motion task."""
    segs = report.get("motion", {}).get("segments")
    if not isinstance(segs, list):
        return ""
    rows = []
    for i, seg in enumerate(segs):
        if "characteristics" not in seg:
            continue
        pre = f"motion.segments.{i}"
        cells = "".join(num_cell(report, f"{pre}.characteristics.{k}") for k in ("C_v", "C_a", "C_j", "torque_index"))
        task = num_cell(report, f"{pre}.vdi2143.task") if has(report, f"{pre}.vdi2143.task") else "<td>—</td>"
        rows.append(f"<tr><td>{i}</td><td>{html.escape(str(seg.get('kind')))}</td>"
                    f"<td>{html.escape(str(seg.get('law')))}</td>{cells}{task}</tr>")
    if not rows:
        return ""
    return ("<h3>Motion laws: characteristic values and VDI 2143 tasks</h3>"
            '<p class="note">Per unit rise over a unit interval: a rise h over duration T peaks at C_v·h/T, '
            "C_a·h/T², C_j·h/T³; C_v·C_a is the torque index; C_j is blank (infinite) where the acceleration "
            "jumps at an end. Task: the state at start–end, R rest, V constant velocity, U reversal, "
            "M motion.</p>"
            '<table class="laws"><tr><th>#</th><th>kind</th><th>law</th><th>C_v</th><th>C_a</th><th>C_j</th>'
            "<th>C_v·C_a</th><th>VDI 2143 task</th></tr>" + "".join(rows) + "</table>")


def _junctions_table(report: Mapping[str, Any], lu: str) -> str:
    """report.json ``motion.junctions``: one row per segment boundary with the jumps of s′, s″, s‴,
    the order of continuity reached and the order the laws promise."""
    junctions = report.get("motion", {}).get("junctions")
    if not isinstance(junctions, list) or not junctions:
        return ""
    out = ["<h3>Segment junctions</h3>",
           '<p class="note">Jumps are right − left of s′, s″, s‴ (per radian) where one segment ends and the '
           "next starts; C<i>n</i>: s … s<sup>(n)</sup> continuous. A junction fails when it reaches less than "
           "the laws on either side promise (the <code>continuity</code> check).</p>",
           '<table class="junctions"><tr><th>at cam angle [deg]</th><th>from → to</th>'
           f"<th>Δs′ [{html.escape(lu)}/rad]</th><th>Δs″ [{html.escape(lu)}/rad²]</th>"
           f"<th>Δs‴ [{html.escape(lu)}/rad³]</th><th>reached C<i>n</i></th><th>promised C<i>n</i></th><th>met</th></tr>"]
    for i, j in enumerate(junctions):
        pre = f"motion.junctions.{i}"
        ok = bool(j.get("ok"))
        cls = "pass" if ok else "fail"
        out.append(
            f'<tr class="{cls}">{num_cell(report, pre + ".at_deg")}'
            f"<td>motion[{j.get('from')}] {html.escape(str(j.get('from_law')))} → motion[{j.get('to')}] "
            f"{html.escape(str(j.get('to_law')))}</td>"
            f"{num_cell(report, pre + '.jumps.velocity')}{num_cell(report, pre + '.jumps.acceleration')}"
            f"{num_cell(report, pre + '.jumps.jerk')}{num_cell(report, pre + '.order')}"
            f"{num_cell(report, pre + '.promised')}"
            f"{num_cell(report, pre + '.ok')}</tr>")
    out.append("</table>")
    return "".join(out)


def _dynamics_section(report: Mapping[str, Any], fig: Mapping[str, str]) -> str:
    """report.json's ``dynamics`` section: the verdict, the numbers, residual vibration, figures."""
    d = report["dynamics"]
    kept = d["contact"]["kept"] is True
    speed = format_number(d["speed_rpm"])
    text = (f"the follower stays on the cam at {speed} rpm" if kept else
            f"the follower LEAVES the cam at {speed} rpm")
    out = [f'<p><span class="verdict {"pass" if kept else "fail"}" id="dynamics-verdict" '
           f'data-key="dynamics.contact.kept" data-value="{"true" if kept else "false"}">{html.escape(text)}</span></p>']
    m = d["model"]
    fu = d["contact"]["unit"]
    lu = d["error"]["unit"]
    tu = d["torque"]["unit"]
    rows = [
        ("analysis speed", "dynamics.speed_rpm", "rpm", None),
        ("effective " + ("inertia" if m["coordinate"] == "arm angle" else "mass"), "dynamics.model.mass",
         m["mass_unit"], None),
        ("train stiffness k_f", "dynamics.model.stiffness", m["stiffness_unit"], None),
        ("return spring rate", "dynamics.model.spring_rate", m["stiffness_unit"], None),
        ("preload", "dynamics.model.preload", m["preload_unit"], None),
        ("damping ratio ζ", "dynamics.model.damping_ratio", "", None),
        ("natural frequency of the train on the cam", "dynamics.model.natural_frequency_hz", "Hz", None),
        ("natural frequency / cam frequency", "dynamics.model.frequency_ratio", "", None),
        ("samples per revolution", "dynamics.model.samples", "", None),
        ("smallest contact force (dynamic)", "dynamics.contact.min_force", fu, "dynamics.contact.min_force_at_deg"),
        ("largest contact force (dynamic)", "dynamics.contact.max_force", fu, "dynamics.contact.max_force_at_deg"),
        ("smallest contact force (rigid follower)", "dynamics.contact.rigid_min_force", fu,
         "dynamics.contact.rigid_min_force_at_deg"),
        ("largest contact force (rigid follower)", "dynamics.contact.rigid_max_force", fu,
         "dynamics.contact.rigid_max_force_at_deg"),
        ("cam rotation with the follower off the cam", "dynamics.contact.off_cam_deg", "deg", None),
        ("largest gap off the cam", "dynamics.contact.max_gap", lu, "dynamics.contact.max_gap_at_deg"),
        ("largest landing speed", "dynamics.contact.max_landing_speed", f"{lu}/s", None),
        ("largest displacement error |q − s|", "dynamics.error.max", lu, "dynamics.error.at_deg"),
        ("largest vibration about the quasi-static deflection", "dynamics.error.max_vibration", lu,
         "dynamics.error.vibration_at_deg"),
        ("jump speed", "dynamics.jump_speed.rpm", "rpm", None),
        ("jump speed / analysis speed", "dynamics.jump_speed.ratio_to_speed", "", None),
        ("rigid follower's jump speed", "dynamics.jump_speed.rigid_rpm", "rpm", None),
        ("sweep from", "dynamics.jump_speed.sweep_from_rpm", "rpm", None),
        ("sweep to", "dynamics.jump_speed.sweep_to_rpm", "rpm", None),
        ("sweep speeds", "dynamics.jump_speed.sweep_points", "", None),
        ("camshaft torque, largest (rigid)", "dynamics.torque.rigid.max", tu, "dynamics.torque.rigid.max_at_deg"),
        ("camshaft torque, smallest (rigid)", "dynamics.torque.rigid.min", tu, "dynamics.torque.rigid.min_at_deg"),
        ("camshaft torque, RMS (rigid)", "dynamics.torque.rigid.rms", tu, None),
        ("work per revolution (rigid)", "dynamics.torque.rigid.work_per_revolution", tu, None),
        ("camshaft torque, largest (dynamic)", "dynamics.torque.dynamic.max", tu,
         "dynamics.torque.dynamic.max_at_deg"),
        ("camshaft torque, smallest (dynamic)", "dynamics.torque.dynamic.min", tu,
         "dynamics.torque.dynamic.min_at_deg"),
        ("camshaft torque, RMS (dynamic)", "dynamics.torque.dynamic.rms", tu, None),
        ("work per revolution (dynamic: the damper's and the landings' losses)",
         "dynamics.torque.dynamic.work_per_revolution", tu, None),
        ("revolutions run (0: periodic solve)", "dynamics.steady_state.revolutions", "", None),
        ("steady state reached", "dynamics.steady_state.periodic", "", None),
    ]
    out.append(fig.get("dynamics", ""))
    out.append(quantity_table(report, rows))
    notes = [f'<span data-key="dynamics.steady_state.method">{html.escape(str(d["steady_state"]["method"]))}</span>']
    jp = d.get("jump_speed")
    if isinstance(jp, Mapping) and jp.get("note"):
        notes.append(f'<span data-key="dynamics.jump_speed.note">{html.escape(str(jp["note"]))}</span>')
    out.append('<p class="note">' + ". ".join(notes) + ".</p>")
    res = d.get("residual_vibration") or []
    if res:
        out.append("<h3>Residual vibration after each rise and return</h3>")
        out.append('<table class="residual"><tr><th>after</th><th>into</th><th>largest vibration</th><th>unit</th>'
                   "<th>at cam angle [deg]</th></tr>")
        for i, r in enumerate(res):
            key = f"dynamics.residual_vibration.{i}"
            out.append(f"<tr><td>motion[{int(r['after'])}] ({html.escape(str(r['kind']))})</td>"
                       f"<td>motion[{int(r['next'])}] ({html.escape(str(r['next_kind']))})</td>"
                       f"{num_cell(report, key + '.amplitude')}<td>{html.escape(lu)}</td>"
                       f"{num_cell(report, key + '.at_deg')}</tr>")
        out.append("</table>")
    out.append(fig.get("jump_speed", ""))
    return "".join(out)


def _verdict(report: Mapping[str, Any]) -> str:
    """report.json's checks.passed / checks.failed, verbatim (nothing when there are no checks)."""
    checks = report.get("checks")
    if not isinstance(checks, Mapping) or "passed" not in checks:
        return ""
    ok = checks["passed"] is True
    failed = html.escape(",".join(str(n) for n in checks.get("failed") or []))
    return (f'<p><a class="plain" href="#checks"><span class="verdict {"pass" if ok else "fail"}" data-key="checks.passed" '
            f'data-value="{"true" if ok else "false"}" data-failed="{failed}">'
            f"{html.escape(checks_verdict(checks))}</span></a></p>")


def buildability_rows(report: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(item, value, status "pass"/"fail"/"") of the buildability verdicts, from report.json.

    The undercut, self-intersection and bore checks raise before any report is written
    (``design_cam``), so a report exists only for a cam that passed them; the numbers shown
    are the margins they were judged on."""
    u = report.get("units", "")
    lu = report.get("motion", {}).get("lift_unit", u)
    rows: list[tuple[str, str, str]] = []
    prof = report.get("profile", {})
    cv = report.get("curvature", {})
    flat = report.get("follower", {}).get("design_curve") == "profile"
    if "min_profile_radius" in cv:
        v = cv["min_profile_radius"]
        what = ("cusp: smallest radius of curvature of the profile > 0" if flat else
                "undercut: smallest convex profile radius of curvature > 0")
        rows.append((what, f"{format_number(v)} {u}", "pass" if v > 0 else "fail"))
    rows.append(("profile self-intersection", "none found (design_cam refuses a crossing profile)", "pass"))
    spec = report.get("spec", {})
    bore = spec.get("cam", {}).get("bore_diameter") if isinstance(spec, Mapping) else None
    if "min_radius" in prof and bore is not None:
        ok = prof["min_radius"] > bore / 2
        rows.append(("bore inside the profile: smallest profile radius > bore radius",
                     f"{format_number(prof['min_radius'])} > {format_number(bore / 2)} {u}", "pass" if ok else "fail"))
    pt = report.get("pitch", {})
    if pt.get("tolerance") is not None:
        ok = pt["max_deviation"] <= pt["tolerance"]
        rows.append(("pitch curve within pitch.tolerance",
                     f"{format_number(pt['max_deviation'])} ≤ {format_number(pt['tolerance'])} {lu}",
                     "pass" if ok else "fail"))
    solid = report.get("solid")
    if isinstance(solid, Mapping) and "valid" in solid:
        ok = solid["valid"] is True and solid.get("solids") == 1
        rows.append(("OCCT: valid, one solid", f"valid {format_number(solid['valid'])}, "
                     f"{format_number(solid.get('solids'))} solid(s)", "pass" if ok else "fail"))
    it = report.get("interpolator")
    if isinstance(it, Mapping) and it.get("within_pitch_tolerance") is not None:
        ok = it["within_pitch_tolerance"] is True
        rows.append(("machining commands within pitch.tolerance", format_number(it["max_deviation"]) + f" {lu}",
                     "pass" if ok else "fail"))
    return rows


def _buildability_section(report: Mapping[str, Any]) -> str:
    rows = buildability_rows(report)
    ok = all(st != "fail" for _, _, st in rows)
    # "buildable"/"unbuildable", not "pass"/"fail": the class "verdict pass" is the design checks'
    # verdict alone, so a reader (or a script) never takes a buildable cam for one that passes
    out = [f'<p><span class="verdict {"buildable" if ok else "unbuildable"}" id="buildable-verdict">'
           f'{"buildable: every buildability check passes" if ok else "NOT buildable: see the red rows"}'
           "</span></p>",
           '<table class="build"><tr><th>check</th><th>value</th><th>status</th></tr>']
    for item, value, st in rows:
        out.append(f'<tr class="{st}"><td>{html.escape(item)}</td><td>{html.escape(value)}</td>'
                   f'<td class="{st}">{st or "—"}</td></tr>')
    out.append("</table>")
    return "".join(out)


def _spec_section(spec: CamSpec, report: Mapping[str, Any]) -> str:
    """Tables of every spec field (values from report["spec"]), the motion table, the TOML."""
    out = []
    if "spec" in report:
        units = spec.units
        rows = [("units", "spec.units", "")]
        for name, (cls, is_list, _req) in SECTIONS.items():
            if is_list:
                continue
            for field, p in params_of(cls).items():
                if has(report, f"spec.{name}.{field}"):
                    rows.append((f"{name}.{field}", f"spec.{name}.{field}", unit_name(p.unit, units)))
        out.append('<table class="spec"><tr><th>field</th><th>value</th><th>unit</th></tr>')
        for label, key, unit in rows:
            out.append(f"<tr><td><code>{html.escape(label)}</code></td>{num_cell(report, key)}"
                       f"<td>{html.escape(unit)}</td></tr>")
        out.append("</table>")
        motion = report["spec"].get("motion", [])
        out.append("<h3>Motion program</h3>")
        out.append('<table class="motion"><tr><th>#</th><th>kind</th><th>from [deg]</th><th>span [deg]</th>'
                   f"<th>lift [{html.escape(units)}]</th><th>law</th><th>junctions</th></tr>")
        start = 0.0
        for i, seg in enumerate(motion):
            cells = []
            for f in ("angle", "lift", "law", "junctions"):
                key = f"spec.motion.{i}.{f}"
                cells.append(num_cell(report, key) if has(report, key) else "<td>—</td>")
            out.append(f"<tr><td>{i}</td><td>{html.escape(str(seg.get('kind')))}</td>"
                       f'<td class="num">{start:g}</td>{"".join(cells)}</tr>')
            start += float(seg.get("angle", 0.0))
        out.append("</table>")
    out.append("<details><summary>The spec as TOML</summary><pre>" + html.escape(to_toml(spec)) +
               "</pre></details>")
    return "".join(out)


DRAWING_LABELS = {
    "file_version": "DXF version", "insunits": "$INSUNITS (4 = mm, 1 = inch)",
    "curves": "profile written as", "chord_tolerance": "chord tolerance",
    "profile_entities": "PROFILE entities", "profile_arcs": "PROFILE arcs", "profile_lines": "PROFILE lines",
    "profile_max_error": "PROFILE entities: max distance from the profile NURBS (two-sided, measured; "
                         "0 for a SPLINE, which is the NURBS data itself)",
    "profile_min_arc_radius": "smallest arc radius",
    "pitch_max_error": "PITCH entities: max distance from the pitch-curve NURBS",
    "profile_poles": "PROFILE SPLINE control points",
    "max_error_by_layer": "entities: max distance from the NURBS they stand for, by layer",
    "exact": "PROFILE is exact (the exact offset of the pitch curve, or the pitch curve itself)",
    "profile_curve": "the profile NURBS is",
    "profile_fit_error": "profile NURBS: max distance from the exact curve it was fitted to",
    "pitch_curve": "the pitch curve is",
}


def _drawing_section(report: Mapping[str, Any]) -> str:
    d = report["drawing"]
    out = ['<table class="kv"><tr><th>item</th><th>value</th></tr>']
    for k, v in d.items():
        label = DRAWING_LABELS.get(k, k.replace('_', ' '))
        for sub in (v if isinstance(v, Mapping) else [None]):     # a dict: one row per entry
            key = f"drawing.{k}" + (f".{sub}" if sub is not None else "")
            out.append(f"<tr><td>{html.escape(label + (f': {sub}' if sub is not None else ''))}</td>"
                       f"{num_cell(report, key)}</tr>")
    out.append("</table>")
    spline = {"spline": "The SPLINE on PROFILE carries the degree, knots, control points and weights of the "
                        "profile NURBS" + (f" (the {html.escape(str(d['profile_curve']))})"
                                           if d.get("profile_curve") else "") + ".",
              "cubic": "The SPLINEs are polynomial cubics within the chord tolerance of the NURBS: every DXF "
                       "reader draws them."}.get(str(d.get("curves")), "")
    out.append('<p class="note">Layers: PROFILE, PITCH, BASE_CIRCLE, PRIME_CIRCLE, BORE, CENTERLINES, '
               f"DIMENSIONS, TITLE (title block with the key numbers, the checks verdict and the motion "
               f"table). {spline}</p>")
    return "".join(out)


def _files_section(report: Mapping[str, Any]) -> str:
    out = ["<table><tr><th>file</th><th>content</th></tr>"]
    for k, v in report["files"].items():
        names = v if isinstance(v, list) else [v]
        for n in names:
            out.append(f"<tr><td><code>{html.escape(str(n))}</code></td><td>{html.escape(k)}</td></tr>")
    out.append("</table>")
    return "".join(out)


# ---- the page's sections, in order ------------------------------------------------------------
#: (id, title, body HTML) of one section of the page
Section = tuple[str, str, str]


@dataclass(frozen=True)
class PageData:
    """What the section views read.

    Attributes:
        spec: the cam's spec (field names and units of the spec tables, the TOML).
        report: the report.json content as written.
        fig: figure key → its ``<figure>`` element (only the figures the report has).
    """

    spec: CamSpec
    report: Mapping[str, Any]
    fig: Mapping[str, str]

    @property
    def u(self) -> str:
        """The length unit ("mm" or "in")."""
        return self.report.get("units", self.spec.units)

    @property
    def lu(self) -> str:
        """The follower's lift unit: the length unit, or "deg" for an arm's rotation."""
        return self.report.get("motion", {}).get("lift_unit", self.u)


def cam_view(p: PageData) -> Section:
    """The cam drawing beside the checks' verdict and the key numbers."""
    report, u, lu = p.report, p.u, p.lu
    key_rows = [
        ("follower", "follower.label", "", None),
        ("base radius R_b (prime circle)", "spec.cam.base_radius", u, None),
        ("base circle radius (the profile at zero lift)", "profile.base_circle_radius", u, None),
        ("smallest profile radius (built)", "profile.min_radius", u, None),
        ("largest profile radius", "profile.max_radius", u, "profile.max_radius_at_deg"),
        ("follower offset e", "follower.offset", u, None),
        ("arm pivot distance d", "follower.pivot_distance", u, None),
        ("arm length L", "follower.arm_length", u, None),
        ("arm angle at zero lift ψ₀", "follower.arm_angle_at_zero_lift_deg", "deg", None),
        ("face offset from the pivot f", "follower.face_offset", u, None),
        ("face normal angle at zero lift β₀", "follower.face_angle_at_zero_lift_deg", "deg", None),
        ("roller radius", "spec.follower.roller_radius", u, None),
        ("bore diameter", "spec.cam.bore_diameter", u, None),
        ("thickness", "spec.cam.thickness", u, None),
        (area_label("area"), "area", f"{u}²", None),
        *_area_rows(report, u),
        ("volume", "volume", f"{u}³", None),
        ("max pressure angle", "pressure_angle.max_deg", "deg", "pressure_angle.at_deg"),
        ("min profile radius of curvature", "curvature.min_profile_radius", u, "curvature.at_deg"),
        ("max follower deviation", "pitch.max_deviation", lu, "pitch.max_deviation_at_deg"),
    ]
    if not p.spec.is_roller:
        key_rows = [r for r in key_rows if r[1] != "spec.follower.roller_radius"]
    return ("cam", "The cam", f'<div class="grid"><div>{p.fig["cam"]}</div><div>'
            f'{_verdict(report)}{quantity_table(report, key_rows)}</div></div>')


def checks_view(p: PageData) -> Section | None:
    """The design checks (when report.json has them): right after the cam, before the curves
    they are judged on."""
    if not isinstance(p.report.get("checks"), Mapping):
        return None
    return ("checks", "Design checks", checks_section(p.report))


def buildability_view(p: PageData) -> Section:
    """The buildability verdicts (after the design checks)."""
    return ("buildability", "Buildability", _buildability_section(p.report))


def spec_view(p: PageData) -> Section:
    """Every spec field, the motion program and the spec as TOML."""
    return ("spec", "Specification", _spec_section(p.spec, p.report))


def motion_view(p: PageData) -> Section:
    """s/v/a/j, their maxima, the solved segments and the junctions."""
    lu = p.lu
    motion_rows = [
        ("largest lift", "motion.max_lift", lu, None),
        ("max |velocity|", "motion.max_velocity", f"{lu}/s", None),
        ("max |acceleration|", "motion.max_acceleration", f"{lu}/s²", None),
        ("max |jerk|", "motion.max_jerk", f"{lu}/s³", None),
    ]
    return ("motion", "Follower motion", p.fig["kinematics"] + quantity_table(p.report, motion_rows)
            + _laws_table(p.report) + _segments_table(p.report, lu) + _junctions_table(p.report, lu))


def pressure_view(p: PageData) -> Section:
    """The pressure angle over the cycle and its maxima, design and built."""
    pa_rows = [
        ("max |φ| (design)", "pressure_angle.max_deg", "deg", "pressure_angle.at_deg"),
        ("signed φ at that angle", "pressure_angle.signed_deg", "deg", None),
        ("max |φ| (built curve)", "pressure_angle.as_built.max_deg", "deg", "pressure_angle.as_built.at_deg"),
    ]
    return ("pressure", "Pressure angle", p.fig["pressure_angle"] + quantity_table(p.report, pa_rows))


def curvature_view(p: PageData) -> Section:
    """The radius of curvature and its minima, design and built."""
    u = p.u
    cv_rows = [
        (f"min convex {p.report.get('follower', {}).get('curve', 'pitch curve')} radius (design)",
         "curvature.min_pitch_radius", u, "curvature.at_deg"),
        ("min convex profile radius (design)", "curvature.min_profile_radius", u, "curvature.at_deg"),
        ("min concave pitch radius (design)", "curvature.min_concave_pitch_radius", u, None),
        ("min convex pitch radius (built)", "curvature.as_built.min_pitch_radius", u, "curvature.as_built.at_deg"),
        ("min convex profile radius (built)", "curvature.as_built.min_profile_radius", u,
         "curvature.as_built.at_deg"),
        ("min concave pitch radius (built)", "curvature.as_built.min_concave_pitch_radius", u, None),
    ]
    return ("curvature", "Radius of curvature", p.fig["curvature"] + quantity_table(p.report, cv_rows))


def accuracy_view(p: PageData) -> Section:
    """The pitch curve's interpolation error, the profile NURBS and the solid's OCCT numbers, and
    what the profile is (exact offset or fit)."""
    report, spec, u, lu = p.report, p.spec, p.u, p.lu
    acc_rows = [
        ("max |s_actual − s|", "pitch.max_deviation", lu, "pitch.max_deviation_at_deg"),
        ("target deviation (pitch.tolerance)", "pitch.tolerance", lu, None),
        ("PH segments M" if pitch_of(spec).exact else "B-spline knot spans", "pitch.segments", "",
         None),
        ("Newton iterations of the spline solve", "pitch.newton_iterations", "", None),
        ("Newton residual (relative)", "pitch.newton_residual", "", None),
        ("pitch-curve arc length" + (" (closed form, PH)" if pitch_of(spec).exact else ""),
         "pitch.arc_length", u, None),
        ("profile NURBS degree", "profile.degree", "", None),
        ("profile NURBS rational", "profile.rational", "", None),
        ("profile poles", "profile.poles", "", None),
        ("profile: max distance from the design-intent profile", "profile.max_error", u,
         "profile.max_error_at_deg"),
        ("profile: fitted offset vs the exact offset of the fitted pitch B-spline",
         "profile.fitted_vs_kernel_offset", u, None),
        ("profile: exact offset of the fitted pitch B-spline vs the design-intent profile",
         "profile.kernel_offset.max_error", u, "profile.kernel_offset.max_error_at_deg"),
        ("solid: OCCT volume", "solid.kernel_volume", f"{u}³", None),
        ("solid: volume of the profile NURBS (Green's theorem × thickness)", "volume", f"{u}³", None),
        ("solid: OCCT cross-section area", "solid.cross_section_area", f"{u}²", None),
        ("solid: cross-section of the profile NURBS (Green's theorem)", "area", f"{u}²", None),
        ("solid: OCCT volume / Green's theorem − 1", "solid.volume_rel_diff", "", None),
        ("solid: OCCT cross-section / Green's theorem − 1", "solid.area_rel_diff", "", None),
    ]
    claim = profile_claim(report, spec.is_roller, u) if "profile" in report else None
    acc_note = ""
    if claim is not None:
        where = ("so the only approximation in the geometry is the pitch curve's interpolation of the "
                 "motion, measured above" if claim.exact else
                 "so the geometry carries both the pitch curve's interpolation error and the fit's error, "
                 "each measured above")
        acc_note = (f'<p class="note" id="profile-claim" data-exact="{str(claim.exact).lower()}">The profile '
                    f"is the {html.escape(claim.text)}, {where}. OCCT's numbers are an independent check of "
                    "the built solid.</p>")
    return ("accuracy", "Interpolation error and accuracy",
            p.fig["deviation"] + quantity_table(report, acc_rows) + acc_note)


def conjugate_view(p: PageData) -> Section | None:
    """A conjugate pair's second cam and the distance error between the rollers (with its figures)."""
    if "second_cam" not in p.report.get("body", {}):          # not a pair
        return None
    u = p.u
    lu2 = "deg" if p.report["body"]["roller_distance_error"]["lift_unit"] == "deg" else u
    cj_rows = [
        ("second roller", "body.second_cam.follower.label", "", None),
        ("second cam from z", "body.second_cam.z.0", u, None),
        ("second cam to z", "body.second_cam.z.1", u, None),
        ("axial gap", "body.gap", u, None),
        ("spacer diameter", "body.spacer_diameter", u, None),
        ("second cam: max |φ| (design)", "body.second_cam.pressure_angle.max_deg", "deg",
         "body.second_cam.pressure_angle.at_deg"),
        ("second cam: max |φ| (built curve)", "body.second_cam.pressure_angle.as_built.max_deg", "deg",
         "body.second_cam.pressure_angle.as_built.at_deg"),
        ("second cam: min convex pitch radius", "body.second_cam.curvature.min_pitch_radius", u,
         "body.second_cam.curvature.at_deg"),
        ("second cam: min convex profile radius", "body.second_cam.curvature.min_profile_radius", u,
         "body.second_cam.curvature.at_deg"),
        ("second cam: smallest radius", "body.second_cam.profile.min_radius", u, None),
        ("second cam: largest radius", "body.second_cam.profile.max_radius", u,
         "body.second_cam.profile.max_radius_at_deg"),
        ("second cam: PH segments M", "body.second_cam.pitch.segments", "", None),
        ("second cam: max |s_actual − s|", "body.second_cam.pitch.max_deviation", lu2,
         "body.second_cam.pitch.max_deviation_at_deg"),
        ("second cam: profile's max distance from the design-intent profile",
         "body.second_cam.profile.max_error", u, "body.second_cam.profile.max_error_at_deg"),
        ("distance error between the rollers: max", "body.roller_distance_error.max", u,
         "body.roller_distance_error.at_deg"),
        ("largest interference", "body.roller_distance_error.largest_interference", u, None),
        ("largest play", "body.roller_distance_error.largest_play", u, None),
        ("max |s₁ − s₂| (lift)", "body.roller_distance_error.lift_max", lu2,
         "body.roller_distance_error.lift_at_deg"),
        ("bound: first + second cam's max deviation", "body.roller_distance_error.lift_bound", lu2, None),
        ("share of the turn the first cam drives", "body.drive.first_cam_share", "", None),
        ("share of the turn the second cam drives", "body.drive.second_cam_share", "", None),
    ]
    return ("conjugate", "Conjugate cams", p.fig["conjugate"] + quantity_table(p.report, cj_rows)
            + p.fig["roller_distance"])


def force_view(p: PageData) -> Section | None:
    """Contact force and Hertz stress over the cycle (when the spec gives a load)."""
    if "force_stress" not in p.fig:
        return None
    return ("force", "Contact force and stress", p.fig["force_stress"])


def dynamics_view(p: PageData) -> Section | None:
    """The follower train at speed (report.json ``dynamics``)."""
    if not isinstance(p.report.get("dynamics"), Mapping):
        return None
    return ("dynamics", "Follower dynamics", _dynamics_section(p.report, p.fig))


def interpolator_view(p: PageData) -> Section | None:
    """The rotational interpolator's commands: the follower motion they give against the design."""
    if "interpolator_kinematics" not in p.fig:
        return None
    lu = p.lu
    ip_rows = [
        ("cam speed", "interpolator.speed_rpm", "rpm", None),
        ("sample period Δt", "interpolator.sample_period", "s", None),
        ("cam rotation per command", "interpolator.step_deg", "deg", None),
        ("commands per revolution", "interpolator.commands", "", None),
        ("max |s_actual − s| at the commands", "interpolator.max_deviation", lu,
         "interpolator.max_deviation_at_deg"),
        ("max |v| from the commands", "interpolator.velocity.max", f"{lu}/s", "interpolator.velocity.at_deg"),
        ("max |v| desired", "interpolator.velocity.desired_max", f"{lu}/s", None),
        ("max |a| from the commands", "interpolator.acceleration.max", f"{lu}/s²",
         "interpolator.acceleration.at_deg"),
        ("max |a| desired", "interpolator.acceleration.desired_max", f"{lu}/s²", None),
        ("increase of max |a| [%]", "interpolator.acceleration.increase_percent", "%", None),
        ("max |j| from the commands", "interpolator.jerk.max", f"{lu}/s³", "interpolator.jerk.at_deg"),
        ("max |j| desired", "interpolator.jerk.desired_max", f"{lu}/s³", None),
        ("increase of max |j| [%]", "interpolator.jerk.increase_percent", "%", None),
    ]
    note = p.report["interpolator"].get("warning")
    warn = f'<p class="note"><b>warning:</b> {html.escape(str(note))}</p>' if note else ""
    return ("interpolator", "Machining commands (rotational PH interpolator)",
            p.fig["interpolator_kinematics"] + quantity_table(p.report, ip_rows) +
            p.fig["interpolator_deviation"] + warn)


def optimise_view(p: PageData) -> Section | None:
    """The optimiser's objective, its scalar entries and the convergence figure."""
    if not isinstance(p.report.get("optimise"), Mapping):
        return None
    body = _objective_note(p.report) + scalars_table(p.report, "optimise", exclude=("history",))
    return ("optimise", "Optimiser", p.fig.get("convergence", "") + body)


def drawing_view(p: PageData) -> Section | None:
    """The DXF: how the profile was written and its measured error."""
    if not isinstance(p.report.get("drawing"), Mapping):
        return None
    return ("drawing", "Manufacturing drawing (DXF)", _drawing_section(p.report))


def files_view(p: PageData) -> Section | None:
    """The files of the output folder (report.json ``files``)."""
    if not isinstance(p.report.get("files"), Mapping):
        return None
    return ("files", "Files", _files_section(p.report))


#: the section views in page order (a view returns None when its data is absent)
VIEWS: tuple[Callable[[PageData], Section | None], ...] = (
    cam_view, checks_view, buildability_view, spec_view, motion_view, pressure_view, curvature_view,
    accuracy_view, conjugate_view, force_view, dynamics_view, interpolator_view, optimise_view, drawing_view,
    files_view)


def page_sections(p: PageData) -> list[Section]:
    """The sections the page has, in order."""
    return [s for s in (view(p) for view in VIEWS) if s is not None]
