"""Where `cam-workbench build` of the default cam spends its time: the process profiled (cProfile)
and its cumulative time split into the imports and the pipeline's stages, each as a share of the
whole.  An import is counted where it happens, inside the first stage that needs it (ezdxf's in
the drawing's row too), so the rows overlap.  cProfile's own overhead inflates every figure (about
1.5–2× here); the shares are the figures.  Prints a Markdown table.

    .venv/bin/python benchmarks/bench_profile_build.py
"""
from __future__ import annotations

import os
import pstats
import subprocess
import sys
import tempfile
from pathlib import Path

from _timing import ROOT  # noqa: E402  (puts the project root on sys.path)

ENV = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))

#: (row, the profiled function: file suffix and function name) — the imports first, then the stages
ROWS = (
    ("import OCP (the kernel)", "cam_workbench/kernel/ocp.py", "require"),
    ("import the design code (cam_workbench.generators, numpy)", "generators/__init__.py", "<module>"),
    ("import ezdxf (within the drawing)", "ezdxf/__init__.py", "<module>"),
    ("the design (PH pitch curve, exact offset, checks, body)", "cam_workbench/commands/common.py", "design_for"),
    ("report.json's numbers (summary stage)", "cam_workbench/pipeline.py", "summary_stage"),
    ("the solid (OCCT) and its check", "cam_workbench/pipeline.py", "solid_stage"),
    ("machining (G-code, interpolator)", "cam_workbench/pipeline.py", "machining_stage"),
    ("the drawing (DXF, its fits and measured errors)", "cam_workbench/pipeline.py", "drawing_stage"),
    ("writing the files (STEP, DXF, report.html with its figures)", "cam_workbench/pipeline.py", "write_outputs"),
)


def main() -> list[str]:
    with tempfile.TemporaryDirectory() as tmp:
        prof = Path(tmp) / "build.prof"
        subprocess.run([sys.executable, "-m", "cProfile", "-o", str(prof), "-m", "cam_workbench.cli", "build",
                        "-o", str(Path(tmp) / "out")], env=ENV, cwd=tmp, stdout=subprocess.DEVNULL, check=True)
        stats = pstats.Stats(str(prof)).stats   # (file, line, name) → (cc, nc, tottime, cumtime, callers)
    total = max(v[3] for v in stats.values())
    rows = ["| part of `build` | profiled s | share |", "|---|---:|---:|"]
    for label, suffix, name in ROWS:
        cum = sum(v[3] for (f, _line, fn), v in stats.items() if f.endswith(suffix) and fn == name)
        rows.append(f"| {label} | {cum:.2f} | {100 * cum / total:.0f} % |")
    rows.append(f"| the whole process | {total:.2f} | 100 % |")
    return rows


if __name__ == "__main__":
    print("\n".join(main()))
