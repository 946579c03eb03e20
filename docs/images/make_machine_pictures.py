"""Make docs/images/machine_timing.png, the timing diagram of the built-in machine ``three_cams``
(docs/examples/machine_three_cams.toml) as ``cam-workbench machine`` draws it, and
docs/images/machine_frame.png, one still of its animation (machine angle 30°, frame 6 of 72:
``write_frame``, docs/animation.md).

    .venv/bin/python docs/images/make_machine_pictures.py
"""
from __future__ import annotations

import json
from pathlib import Path

from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.machine_animation import write_frame
from cam_workbench.exporters.machine_plots import timing_chart
from cam_workbench.exporters.machine_report import machine_json_text
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.machine.frames import machine_frames, turn_angles
from cam_workbench.machine import ANIMATION_STEP_DEG, Machine

HERE = Path(__file__).resolve().parent


def main() -> None:
    """Write machine_timing.png and machine_frame.png beside this script."""
    machine = Machine(HERE.parent / "examples" / "machine_three_cams.toml")
    result = machine.analyse()
    report = json.loads(machine_json_text(result.summary(), {}))
    (HERE / "machine_timing.png").write_bytes(png_bytes(svg(timing_chart(result, report), "timing")))
    print(HERE / "machine_timing.png")
    frames = machine_frames(machine.spec, [design_cam(c.spec) for c in machine.spec.cams], turn_angles(ANIMATION_STEP_DEG))
    print(write_frame(frames, 6, HERE / "machine_frame.png"))


if __name__ == "__main__":
    main()
