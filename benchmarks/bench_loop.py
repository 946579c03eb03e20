"""The designer's loop (issue 22): whole commands, each example's solid and report, and the FreeCAD
recompute after a change, each as a ratio to the floor beside it.  CPU seconds (the process's
user + system time, children included): other load on the machine disturbs them less than wall
time; each figure is the smallest of a few runs.  Prints Markdown tables.

    .venv/bin/python benchmarks/bench_loop.py
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

from _timing import ROOT, cpu_best_of  # noqa: E402  (puts the project root on sys.path)

PY = sys.executable
CLI = [PY, "-m", "cam_workbench.cli"]
ENV = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
EXAMPLES = ("default", "groove", "conjugate", "cylindrical")


def process_cpu(cmd: list[str], repeat: int = 3, cwd: str | None = None) -> float:
    """Smallest CPU time [s] (user + system) of ``repeat`` runs of the process ``cmd``."""
    best = float("inf")
    for _ in range(repeat):
        before = os.times()
        subprocess.run(cmd, env=ENV, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        after = os.times()
        best = min(best, (after.children_user - before.children_user) + (after.children_system - before.children_system))
    return best


def commands() -> list[str]:
    rows = ["| what | CPU [s] | floor | floor CPU [s] | ratio |", "|---|---:|---|---:|---:|"]
    with tempfile.TemporaryDirectory() as tmp:
        floors = {
            "Python start-up": process_cpu([PY, "-c", "pass"]),
            "import numpy, scipy.linalg": process_cpu([PY, "-c", "import numpy, scipy.linalg"]),
            "import OCP": process_cpu([PY, "-c", "import OCP"]),
        }
        runs = [
            ("`cam-workbench --help`", CLI + ["--help"], "Python start-up"),
            ("`cam-workbench check`", CLI + ["check"], "import numpy, scipy.linalg"),
            ("`cam-workbench build` (default cam, every output)",
             CLI + ["build", "-o", str(Path(tmp) / "b"), "--replace"], "import OCP"),
        ]
        for what, cmd, floor in runs:
            t = process_cpu(cmd)
            rows.append(f"| {what} | {t:.2f} | {floor} | {floors[floor]:.2f} | {t / floors[floor]:.1f}× |")
    return rows


def api() -> list[str]:
    """Each example's ``solid()`` and ``report()`` after the imports and a first build (in this
    process), beside its design."""
    from cam_workbench import Cam
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec.examples import example_spec

    Cam.example("default").solid()          # imports and first-use costs out of the way
    rows = ["| example | design [s] | solid() [s] | report() [s] | solid + report / design |",
            "|---|---:|---:|---:|---:|"]
    for ex in EXAMPLES:
        spec = example_spec(ex)
        t_design = cpu_best_of(lambda: design_cam(spec), 3)
        t_solid = cpu_best_of(lambda: Cam(spec).solid(), 2)
        t_report = cpu_best_of(lambda: Cam(spec).report(), 2)
        rows.append(f"| {ex} | {t_design:.3f} | {t_solid:.3f} | {t_report:.3f} | "
                    f"{(t_solid + t_report) / t_design:.0f}× |")
    return rows


_FREECAD = textwrap.dedent("""
    import json, sys, time
    sys.path.insert(0, {root!r})
    import FreeCAD
    from cam_workbench.freecad.feature import create
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec.examples import example_spec
    out = {{}}
    for ex in {examples!r}:
        doc = FreeCAD.newDocument(ex)
        spec = example_spec(ex)
        cam = create(doc, spec.to_dict(), name="cam")
        doc.recompute()
        # the cam's size: the base radius (a cylindrical cam's pitch radius, which the base radius follows)
        sizes = [p for p in ("CamCylinderRadius", "CamBaseRadius") if p in cam.PropertiesList
                 and (p == "CamBaseRadius" or spec.cam.cylinder_radius is not None)]
        times = []
        for k in range(5):
            for p in sizes:
                setattr(cam, p, getattr(cam, p).Value + (0.25 if k % 2 == 0 else -0.25))
            t = time.process_time()
            doc.recompute()
            times.append(time.process_time() - t)
        d = []
        for k in range(5):
            t = time.process_time()
            design_cam(spec)
            d.append(time.process_time() - t)
        out[ex] = dict(recompute=min(times), design=min(d), status=cam.Status)
    out["version"] = ".".join(FreeCAD.Version()[:3])
    open({result!r}, "w").write(json.dumps(out))
""")


def freecad() -> list[str]:
    """FreeCAD (``freecadcmd``, the FreeCAD on PATH) recompute after a size change, beside the
    design alone in the same process."""
    exe = shutil.which("freecadcmd")
    if exe is None:
        return ["(no freecadcmd on PATH: FreeCAD recompute not measured)"]
    with tempfile.TemporaryDirectory() as tmp:
        result = Path(tmp) / "result.json"
        script = Path(tmp) / "bench.py"
        script.write_text(_FREECAD.format(root=str(ROOT), examples=EXAMPLES, result=str(result)), encoding="utf-8")
        subprocess.run([exe, str(script)], cwd=tmp, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       timeout=900, check=False)
        if not result.exists():
            return ["(freecadcmd did not finish the script: FreeCAD recompute not measured)"]
        data = json.loads(result.read_text())
    rows = [f"FreeCAD {data.pop('version')}", "",
            "| example | recompute CPU [ms] | the design alone [ms] | ratio | status |", "|---|---:|---:|---:|---|"]
    for ex, r in data.items():
        rows.append(f"| {ex} | {1e3 * r['recompute']:.0f} | {1e3 * r['design']:.0f} | "
                    f"{r['recompute'] / r['design']:.1f}× | {r['status']} |")
    return rows


if __name__ == "__main__":
    print("### Commands (whole processes, CPU seconds, best of 3)\n")
    print("\n".join(commands()))
    print("\n### The API after imports (CPU seconds, best of 2–3)\n")
    print("\n".join(api()))
    print("\n### FreeCAD recompute after a size change (CPU, best of 5)\n")
    print("\n".join(freecad()))
