"""A machine's report: machine.json (the source of every number) and machine.html — the timing
diagram, the torque plot, the flywheel and one table of every cam's design checks (each row read
from that cam's report.json ``checks`` section as machine.json holds it), every number a cell
carrying its machine.json path (``data-key``) and exact value (``data-value``), as report.html's
cells do (:mod:`.report_cells`)."""
from __future__ import annotations

import html
from typing import Any, Mapping

from cam_workbench.generators import __version__

from .report_cells import has, num_cell
from .report_html import CSS
from .report_json import report_json_text

JSON_NAME = "machine.json"
HTML_NAME = "machine.html"


def machine_json_text(summary: Mapping[str, Any], files: Mapping[str, Any]) -> str:
    """machine.json: ``summary`` with ``files`` (NaN/inf as null)."""
    return report_json_text(dict(summary), dict(files))


def _rows(report: Mapping[str, Any], rows: list[tuple[str, str, str]]) -> str:
    """A key/value table: (label, machine.json path, unit) rows whose path exists."""
    out = ['<table class="q"><tr><th>quantity</th><th>value</th><th>unit</th></tr>']
    for label, key, unit in rows:
        if has(report, key):
            out.append(f"<tr><td>{html.escape(label)}</td>{num_cell(report, key)}<td>{html.escape(unit)}</td></tr>")
    out.append("</table>")
    return "".join(out)


def _torque_table(report: Mapping[str, Any]) -> str:
    unit = report["torque"]["unit"]
    cols = (("max", "max"), ("max_at_deg", "at [deg]"), ("min", "min"), ("min_at_deg", "at [deg]"),
            ("mean", "mean"), ("rms", "RMS"))
    head = "".join(f"<th>{html.escape(t)}</th>" for _k, t in cols)
    out = [f'<table class="q"><tr><th>cam</th><th>phase [deg]</th>{head}</tr>']
    for i, cam in enumerate(report["cams"]):
        cells = "".join(num_cell(report, f"cams.{i}.torque.{k}") for k, _t in cols)
        out.append(f"<tr><td>{html.escape(cam['name'])}</td>{num_cell(report, f'cams.{i}.phase_deg')}{cells}</tr>")
    cells = "".join(num_cell(report, f"torque.{k}") for k, _t in cols)
    out.append(f"<tr><td><b>total</b></td><td></td>{cells}</tr></table>")
    return f"<p class=\"note\">Torques in {html.escape(unit)}; angles are machine angles.</p>" + "".join(out)


def checks_table(report: Mapping[str, Any]) -> str:
    """One table of every cam's design checks: a row per cam and check, its status (a failing
    row shown failing), value, limit, unit and cam angle — as each cam's report.json says."""
    out = ['<table class="checks"><tr><th>cam</th><th>check</th><th>status</th><th>value</th><th>limit</th>'
           "<th>unit</th><th>at cam angle [deg]</th></tr>"]
    for i, cam in enumerate(report["cams"]):
        results = (cam.get("checks") or {}).get("results") or {}
        for name, r in results.items():
            base = f"cams.{i}.checks.results.{name}"
            status = str(r.get("status"))
            cls = ' class="fail"' if status == "fail" else ""
            out.append(f'<tr{cls} data-cam="{html.escape(cam["name"])}" data-check="{html.escape(name)}">'
                       f"<td>{html.escape(cam['name'])}</td><td>{html.escape(name)}</td>"
                       f'<td class="{html.escape(status)}" data-key="{base}.status">{html.escape(status)}</td>'
                       f"{num_cell(report, base + '.value')}{num_cell(report, base + '.limit')}"
                       f"<td>{html.escape(str(r.get('unit') or ''))}</td>{num_cell(report, base + '.at_deg')}</tr>")
    out.append("</table>")
    return "".join(out)


def linkage_table(report: Mapping[str, Any]) -> str:
    """The tools: each cam's tool, what drives it (its linkage, or the follower's own point), where
    its [[motion]] is given, the tool's extent in the machine plane and, through a linkage, its
    largest displacement, |v|, |a| (machine.json's ``cams[i].tool_path`` and ``linkage``)."""
    out = ['<table class="q"><tr><th>cam</th><th>tool</th><th>driven by</th><th>motion given at</th>'
           "<th>x min</th><th>x max</th><th>y min</th><th>y max</th><th>tool unit</th><th>max displacement</th>"
           "<th>max |v| [/s]</th><th>max |a| [/s²]</th></tr>"]
    for i, cam in enumerate(report["cams"]):
        tp = cam.get("tool_path")
        if not tp:
            continue
        lk = cam.get("linkage")
        tool = (cam.get("tool") or {}).get("label") or ""
        drive = lk["kind"] if lk else "the follower's own point"
        cells = "".join(num_cell(report, f"cams.{i}.tool_path.{k}") for k in ("x_min", "x_max", "y_min", "y_max"))
        if lk:
            cells += f"<td>{html.escape(str(lk['tool_unit']))}</td>" + "".join(
                num_cell(report, f"cams.{i}.linkage.tool_motion.{k}")
                for k in ("max_displacement", "max_velocity", "max_acceleration"))
        else:
            cells += "<td></td><td></td><td></td><td></td>"
        out.append(f"<tr><td>{html.escape(cam['name'])}</td><td>{html.escape(tool)}</td><td>{html.escape(drive)}</td>"
                   f"<td>{html.escape(str(lk['motion_at']) if lk else '—')}</td>{cells}</tr>")
    out.append("</table>")
    return f'<p class="note">Tool points in the machine plane [{html.escape(str(report["units"]))}].</p>' + "".join(out)


def clearance_table(report: Mapping[str, Any]) -> str:
    """One row per [[clearance]] pair: required, smallest distance, machine angle, margin, error
    bound, status (a failing row shown failing, with its remedy) — machine.json's ``clearance``."""
    c = report["clearance"]
    unit = html.escape(str(c["unit"]))
    ok = ("pass", "every pair keeps its clearance") if c["passed"] else ("fail", "FAIL: " + ", ".join(c["failed"]))
    out = [f'<p><span class="verdict {ok[0]}" data-key="clearance.passed">{html.escape(ok[1])}</span></p>',
           f'<table class="checks"><tr><th>pair (A / B)</th><th>status</th><th>required [{unit}]</th>'
           f"<th>smallest distance [{unit}]</th><th>at machine angle [deg]</th><th>margin [{unit}]</th>"
           f"<th>error bound [{unit}]</th><th>remedy</th></tr>"]
    for k, r in enumerate(c["pairs"]):
        base = f"clearance.pairs.{k}"
        status = str(r["status"])
        cls = ' class="fail"' if status == "fail" else ""
        shown = "FAIL" if status == "fail" else status
        remedy = "—"
        if r.get("remedy"):
            remedy = (f'{html.escape(r["remedy"]["text"])} (<span data-key="{base}.remedy.shift" '
                      f'data-value="{r["remedy"]["shift"]!r}">shift</span>)')
        out.append(f'<tr{cls} data-pair="{html.escape(r["name"])}"><td>{html.escape(r["name"])}</td>'
                   f'<td class="{html.escape(status)}" data-key="{base}.status">{html.escape(shown)}</td>'
                   + "".join(num_cell(report, f"{base}.{key}") for key in
                             ("required", "distance", "at_deg", "margin", "error_bound"))
                   + f"<td>{remedy}</td></tr>")
    out.append("</table>")
    return "".join(out)


def phase_sweep_table(report: Mapping[str, Any]) -> str:
    """machine.json's ``phase_sweep``: the swept cam's phase ranges that keep each clearance, and
    their intersection."""
    ps = report["phase_sweep"]
    out = [f"<p>Phases of <b>{html.escape(str(ps['cam']))}</b> (now "
           f'<span data-key="phase_sweep.phase_deg">{ps["phase_deg"]:.6g}</span>°) that keep every clearance it '
           f"takes part in: " + ", ".join(
               f'<span data-key="phase_sweep.intervals.{k}">{a:.6g}°–{b:.6g}°</span>'
               for k, (a, b) in enumerate(ps["intervals"])) + (" (none)" if not ps["intervals"] else "")
           + f'; its phase now <span data-key="phase_sweep.current_phase_passes">'
             f'{"passes" if ps["current_phase_passes"] else "FAILS"}</span>.</p>',
           '<table class="q"><tr><th>pair</th><th>with</th><th>required</th><th>smallest clearance over the '
           "phases</th><th>largest</th><th>error bound</th><th>phases keeping it [deg]</th></tr>"]
    for k, r in enumerate(ps["pairs"]):
        base = f"phase_sweep.pairs.{k}"
        iv = ", ".join(f"{a:.6g}–{b:.6g}" for a, b in r["intervals"]) or "none"
        out.append(f"<tr><td>{html.escape(r['name'])}</td><td>{html.escape(r['other'])}</td>"
                   + "".join(num_cell(report, f"{base}.{key}") for key in
                             ("required", "min_clearance", "max_clearance", "error_bound"))
                   + f'<td data-key="{base}.intervals">{html.escape(iv)}</td></tr>')
    out.append("</table>")
    return "".join(out) + shortest_cycle_table(report)


def shortest_cycle_table(report: Mapping[str, Any]) -> str:
    """machine.json's ``phase_sweep.shortest_cycle``: how much earlier the swept cam's motion can
    start keeping every clearance, the overlap it gains on the motion it follows, the clearance
    there and the cycle time it would give (under the stated assumption), or the note why not."""
    sc = report["phase_sweep"]["shortest_cycle"]
    key = "phase_sweep.shortest_cycle"
    head = "<h3>Shortest cycle</h3>"
    if sc["note"]:
        return head + f'<p data-key="{key}.note">{html.escape(str(sc["note"]))}</p>'
    f, mo = sc["follows"], sc["motion"]
    unit = html.escape(str(report["phase_sweep"]["unit"]))
    text = (f'<p><span data-key="{key}.motion.event">{html.escape(mo["event"])}</span> follows '
            f'<span data-key="{key}.follows.event">{html.escape(f["event"])}</span> (of '
            f'<span data-key="{key}.follows.cam">{html.escape(f["cam"])}</span>); limited by '
            f'<span data-key="{key}.limited_by">{html.escape(str(sc["limited_by"]))}</span>'
            + (f' ({html.escape(", ".join(sc["binding_pairs"]))})' if sc["binding_pairs"] else "") + ". "
            f'Assumed: <span data-key="{key}.assumption">{html.escape(sc["assumption"])}</span>; it '
            f'<span data-key="{key}.assumption_holds">{"holds" if sc["assumption_holds"] else "does NOT hold"}</span>'
            " here.</p>")
    rows = _rows(report, [
        ("its motion starts now at", f"{key}.motion.start_deg", "deg"),
        ("the followed motion starts at", f"{key}.follows.start_deg", "deg"),
        ("the followed motion ends at", f"{key}.follows.end_deg", "deg"),
        ("the followed motion's span", f"{key}.follows.span_deg", "deg"),
        ("earliest phase keeping every clearance", f"{key}.phase_deg", "deg"),
        ("machine angle saved", f"{key}.saved_deg", "deg"),
        ("overlap now", f"{key}.current_overlap_deg", "deg"),
        ("overlap at the earliest phase", f"{key}.overlap_deg", "deg"),
        ("cycle time now", f"{key}.cycle_time_s", "s"),
        ("shortest cycle time", f"{key}.shortest_cycle_time_s", "s"),
        ("cycles per minute then", f"{key}.cycles_per_min", "1/min"),
        ("whole machine's longest dwell now", f"{key}.machine_dwell_deg", "deg"),
        ("… at the earliest phase", f"{key}.machine_dwell_at_phase_deg", "deg"),
        ("dwell gained", f"{key}.dwell_gained_deg", "deg")])
    out = [f'<table class="q"><tr><th>pair at the earliest phase</th><th>required [{unit}]</th>'
           f"<th>smallest distance [{unit}]</th><th>margin [{unit}]</th><th>at machine angle [deg]</th>"
           f"<th>error bound [{unit}]</th></tr>"]
    for k, c in enumerate(sc["clearance_at_phase"]):
        out.append(f"<tr><td>{html.escape(c['name'])}</td>" + "".join(
            num_cell(report, f"{key}.clearance_at_phase.{k}.{q}")
            for q in ("required", "distance", "margin", "at_deg", "error_bound")) + "</tr>")
    out.append("</table>")
    return head + text + rows + "".join(out)


def animation_section(report: Mapping[str, Any]) -> str:
    """The mechanism in motion: machine.json's ``animation`` — the GIF as an ``<img>`` (an MP4 as a
    ``<video>``) beside machine.html, its frames and step from the dict — or its note."""
    a = report.get("animation") or {}
    if not a.get("file"):
        return f'<p data-key="animation.note">{html.escape(str(a.get("note") or "no animation"))}</p>'
    src = html.escape(str(a["file"]))
    caption = (f'<figcaption>The mechanism over one turn: <span data-key="animation.frames">{a["frames"]}</span> '
               f'frames, one every <span data-key="animation.step_deg">{a["step_deg"]:g}</span>° of machine angle, '
               f'at <span data-key="animation.fps">{a["fps"]}</span> frames per second. Every cam\'s axis is at '
               "the machine plane's origin; the picture shifts each cam's group (cam, follower, linkage, tool) "
               "to its place in the row.</figcaption>")
    media = (f'<video src="{src}" controls loop muted></video>' if a.get("format") == "mp4"
             else f'<img src="{src}" alt="the machine in motion" style="max-width:100%">')
    return f'<figure id="fig-animation">{media}{caption}</figure>'


def machine_html(report: Mapping[str, Any], figures: Mapping[str, str]) -> str:
    """machine.html: one self-contained page (inline SVG figures ``figures["timing"]`` and
    ``figures["torque"]``, no scripts; the animation beside it, machine.gif or machine.mp4, linked by
    an ``<img>`` or ``<video>``) built from machine.json's dict ``report``."""
    m = report["machine"]
    u = report["units"]
    tq_unit = report["torque"]["unit"]
    ck = report["checks"]
    verdict = ("pass", "every cam passes its design checks") if ck["passed"] else \
        ("fail", "failing: " + ", ".join(ck["failed"]))
    cams = ", ".join(f'<a href="{html.escape(c["folder"])}/report.html">{html.escape(c["name"])}</a>'
                     for c in report["cams"])
    files = report.get("files") or {}
    sections = [
        ("camshaft", "Camshaft", _rows(report, [
            ("speed", "machine.speed_rpm", "rpm"), ("angular speed ω", "machine.omega_rad_s", "rad/s"),
            ("speed fluctuation C_s", "machine.speed_fluctuation", ""),
            ("grid step", "machine.grid_step_deg", "deg"), ("grid points", "machine.samples", ""),
            ("cams", "machine.cams", "")]) + f"<p>Cams (each built as <code>cam-workbench build</code> builds it, "
                                            f"in its own folder): {cams}.</p>"),
        ("timing", "Timing diagram", f'<figure id="fig-timing" data-svg="{html.escape(str(files.get("timing_svg", "")))}">'
                                     f"{figures['timing']}<figcaption>Displacement, velocity and acceleration of "
                                     "every follower against the machine angle, and dashed of every tool a linkage "
                                     "drives; each rise and return marked at its start and end and labelled; below, "
                                     "every tool point's x and y in the machine plane.</figcaption></figure>"),
        ("torque", "Camshaft torque", f'<figure id="fig-torque">{figures["torque"]}<figcaption>Each cam\'s camshaft '
                                      "torque (the rigid follower train's, by virtual work T = Q·u′) at the machine "
                                      "angle and their sum; below, the energy E(θ) = ∫(T − T_mean)dθ.</figcaption>"
                                      "</figure>" + _torque_table(report) + _rows(report, [
                                          ("total torque: largest |T|", "torque.peak", tq_unit),
                                          ("work per turn", "torque.work_per_turn", f"{tq_unit}·rad")])),
        ("flywheel", "Flywheel", _rows(report, [
            ("energy fluctuation ΔE = max E − min E", "flywheel.energy_fluctuation_J", "J"),
            ("E at its maximum", "flywheel.energy_max_at_deg", "deg"),
            ("E at its minimum", "flywheel.energy_min_at_deg", "deg"),
            ("coefficient of speed fluctuation C_s", "flywheel.speed_fluctuation", ""),
            ("flywheel inertia I = ΔE/(C_s·ω²)", "flywheel.inertia_kg_m2", "kg·m²")])),
        ("checks", "Design checks", f'<p><span class="verdict {verdict[0]}" data-key="checks.passed">'
                                    f"{html.escape(verdict[1])}</span></p>" + checks_table(report)),
    ]
    sections.insert(2, ("tools", "Tools", linkage_table(report)))
    if "animation" in report:
        sections.insert(3, ("animation", "In motion", animation_section(report)))
    if "clearance" in report:
        sections.append(("clearance", "Clearances", clearance_table(report)))
    if "phase_sweep" in report:
        sections.append(("phase-sweep", "Phase sweep", phase_sweep_table(report)))
    nav = "".join(f'<a href="#{sid}">{html.escape(t)}</a>' for sid, t, _ in sections)
    body = "\n".join(f'<section id="{sid}"><h2>{html.escape(t)}</h2>\n{b}\n</section>' for sid, t, b in sections)
    title = html.escape(str(m["name"]))
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{title} — machine report</title>\n"
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<style>{CSS}</style>\n</head>\n<body>\n<main>\n<h1>{title}</h1>\n"
            f"<p class=\"sub\">{len(report['cams'])} cams on one camshaft · units {html.escape(u)} · made by "
            f"cam_workbench {html.escape(__version__)}</p>\n<nav>{nav}</nav>\n{body}\n</main>\n</body>\n</html>\n")


__all__ = ["HTML_NAME", "JSON_NAME", "animation_section", "checks_table", "clearance_table", "linkage_table", "machine_html",
           "machine_json_text", "phase_sweep_table", "shortest_cycle_table"]
