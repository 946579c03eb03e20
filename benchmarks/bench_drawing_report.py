"""DXF and report benchmarks: the exact SPLINE against the polynomial cubic SPLINE every reader
draws (the default) and the arcs and polyline a spline-less machine needs (entities, file size,
write time, measured error — ratios to the exact spline), and the time to draw the report.
Prints Markdown tables.

    .venv/bin/python benchmarks/bench_drawing_report.py
"""
from __future__ import annotations

import tempfile
from pathlib import Path

from _timing import best_of  # noqa: E402  (puts the project root on sys.path)

from cam_workbench.exporters.dxf import write_dxf  # noqa: E402
from cam_workbench.exporters.report_html import render_report  # noqa: E402
from cam_workbench.generators import default_spec, design_cam  # noqa: E402




def bench_dxf() -> list[str]:
    rows = ["| M | curves | tolerance [mm] | PROFILE entities / segments | max error [mm] | file [kB] "
            "| size / spline | write [ms] | time / spline |", "|---:|---|---:|---:|---:|---:|---:|---:|---:|"]
    with tempfile.TemporaryDirectory() as tmp:
        for m in (60, 240):
            base = default_spec().replace(**{"pitch.segments": m})
            ref_size = ref_time = None
            for curves, tol in (("spline", None), ("cubic", 1e-3), ("cubic", 1e-5), ("arcs", 1e-3), ("arcs", 1e-5),
                                ("polyline", 1e-3), ("polyline", 1e-5)):
                changes = {"drawing.curves": curves}
                if tol is not None:
                    changes["drawing.chord_tolerance"] = tol
                design = design_cam(base.replace(**changes))
                summary = design.summary()
                path = Path(tmp) / f"{m}_{curves}_{tol}.dxf"
                infos = []
                t = best_of(lambda: infos.append(write_dxf(design, path, summary)))
                info = infos[-1]
                size = path.stat().st_size / 1024
                if curves == "spline":
                    ref_size, ref_time = size, t
                n = {"polyline": info.profile.lines, "cubic": f"1 ({info.profile.poles} poles)",
                     "spline": f"1 ({info.profile.poles} poles)"}.get(curves, info.profile.entities)
                rows.append(f"| {m} | {curves} | {tol if tol else 'exact'} | {n} | {info.profile.max_error:.2e} "
                            f"| {size:.0f} | {size / ref_size:.2f}× | {1e3 * t:.0f} | {t / ref_time:.2f}× |")
    return rows


def bench_report() -> list[str]:
    rows = ["| M | design [ms] | summary [ms] | report: 5 figures as SVG [ms] | … and as PNG (--plots) [ms] "
            "| HTML [kB] |", "|---:|---:|---:|---:|---:|---:|"]
    for m in (60, 240):
        spec = default_spec().replace(**{"pitch.segments": m})
        t_design = best_of(lambda: design_cam(spec), 3)
        design = design_cam(spec)
        t_sum = best_of(lambda: design.summary(), 3)
        report = {**design.summary(), "spec": spec.to_dict()}
        out = []
        t_rep = best_of(lambda: out.append(render_report(design, report)), 2)
        t_png = best_of(lambda: render_report(design, report, pngs=True), 2)
        rows.append(f"| {m} | {1e3 * t_design:.0f} | {1e3 * t_sum:.0f} | {1e3 * t_rep:.0f} | {1e3 * t_png:.0f} "
                    f"| {len(out[-1][0].encode()) / 1024:.0f} |")
    return rows


if __name__ == "__main__":
    design_cam(default_spec())  # warm-up: imports and caches
    print("### DXF: exact spline vs cubic spline, arcs and polyline (default cam)\n")
    print("\n".join(bench_dxf()))
    print("\n### Report (default cam)\n")
    print("\n".join(bench_report()))
