"""VDI 2143 motion tasks: each rise or return of a program classified by the state of motion at
its two ends (VDI 2143 Blatt 1, *Bewegungsgesetze für Kurvengetriebe*, 1980: the boundary
conditions a motion law has to meet).

At each end the state is one of

* ``R`` rest: v = 0 and a = 0 (VDI "Rast"), and always next to a dwell (the dwell sets the task,
  even where a law's acceleration jumps there, as a harmonic's does);
* ``V`` constant velocity: v ≠ 0, a = 0 (VDI "G", Geschwindigkeit);
* ``U`` reversal: v = 0, a ≠ 0, the follower turns back there (VDI "Umkehr");
* ``M`` general motion: v ≠ 0, a ≠ 0 (VDI "B", Bewegung);

and the segment's task is "start-end": ``R-R`` (rest to rest), ``R-V``, ``V-R``, ``V-V``, ``R-U``,
``U-R``, ``U-U``, … v and a are the segment's own one-sided values at its ends (the program's s′,
s″ there); zero means within 1e-8 of the segment's scale |h|/β (|h|/β² for a).
"""
from __future__ import annotations

from typing import Any

import numpy as np

#: relative tolerance of "zero" against |h|/βⁿ
ZERO_TOL = 1e-8

STATE_NAMES = {"R": "rest", "V": "constant velocity", "U": "reversal", "M": "motion"}
#: the letters VDI 2143 itself uses for each state
VDI_LETTERS = {"R": "R", "V": "G", "U": "U", "M": "B"}


def end_state(velocity: float, acceleration: float, v_scale: float, a_scale: float) -> str:
    """The state letter (R, V, U, M) of velocity ``velocity`` and acceleration ``acceleration``
    (per rad, per rad²) against their scales |h|/β, |h|/β²."""
    moving = abs(velocity) > ZERO_TOL * v_scale
    accelerating = abs(acceleration) > ZERO_TOL * a_scale
    return ("M" if accelerating else "V") if moving else ("U" if accelerating else "R")


def classify_program(program: Any) -> list[dict[str, Any] | None]:
    """Per segment of ``program`` (a :class:`~.program.MotionProgram`): ``{"task": "R-R", "start":
    "R", "end": "R", "vdi_task": "R-R", "name": "rest to rest"}`` for a rise or return (``vdi_task``
    in VDI's own letters), None for a dwell."""
    n = len(program.starts)
    k = np.arange(n)
    ends = np.stack([program.starts, program.starts + program.spans], axis=1)      # (n, 2)
    kin = program.evaluate(ends.ravel(), np.repeat(k, 2))
    v, a = kin.ds.reshape(n, 2), kin.d2s.reshape(n, 2)
    out: list[dict[str, Any] | None] = []
    for i in range(n):
        if program.laws[i] is None:
            out.append(None)
            continue
        h, beta = abs(float(program.lifts[i])), float(program.spans[i])
        states = []
        for e, nb in ((0, (i - 1) % n), (1, (i + 1) % n)):
            if program.laws[nb] is None:              # next to a dwell: rest, as the dwell demands
                states.append("R")
            else:
                states.append(end_state(float(v[i, e]), float(a[i, e]), h / beta, h / beta**2))
        out.append({"task": f"{states[0]}-{states[1]}", "start": states[0], "end": states[1],
                    "vdi_task": f"{VDI_LETTERS[states[0]]}-{VDI_LETTERS[states[1]]}",
                    "name": f"{STATE_NAMES[states[0]]} to {STATE_NAMES[states[1]]}"})
    return out
