"""The rotational PH interpolator: machining commands of the cam at a constant angular
speed (paper §3.2, Eq. 12–15), and the follower motion those commands produce.

The cam turns at ω [rad/s]; a command is issued every sample period Δt, at cam angles

    θ_k = k·ω·Δt,   k = 0 … N−1,   N = ⌈2π / (ωΔt)⌉   (one revolution).

For each θ_k the PH segment i whose junction angles bracket θ_k is found by
``searchsorted`` and Eq. 13,

    Re(e^{iδθ_k}·r_i(ξ)) = e        (δ = +1 ccw — the paper's case —, −1 cw),

is solved for ξ by Newton's method (Eq. 14).  The paper starts each Newton solve
from the previous command's root, which is sequential; here every command starts
from a cubic Hermite guess of ξ(θ) inside its segment (ξ and dξ/dθ are known exactly
at the junctions, where ξ = 0 or 1), so that one vectorised Newton sweep over all
commands converges in 2–3 steps (:class:`cam_workbench.generators.pitch.contact.FollowerLineSolver`).
The command is the point r_i(ξ_k) in the cam frame (Eq. 15) and the follower
displacement it produces is s_actual = Im(e^{iδθ_k}·r_i(ξ_k)) − s₀.

Kinematics of the produced follower motion are finite differences of s_actual at Δt,
as in the paper's Figures 4–8 (:func:`finite_differences`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SolveError
from ..pitch.contact import Contact, FollowerLineSolver
from ..pitch.ph import PitchCurve
from ..pitch.contact import horner

TWO_PI = 2.0 * np.pi
#: Finite-difference schemes for the actual kinematics (see :func:`finite_differences`).
SCHEMES = ("backward", "central")
#: The scheme reported as the actual kinematics: backward differences are what a
#: controller can compute from past commands, and they reproduce the paper's Table 2.
DEFAULT_SCHEME = "backward"
#: Steps above this many degrees per command get a warning in the report.
COARSE_STEP_DEG = 1.0
CHUNK = 1 << 15   # commands per vectorised solve (keeps the working set in cache)
MAX_COMMANDS = 50_000_000


def command_count(omega: float, sample_period: float) -> int:
    """Commands per revolution: N = ⌈2π/(ωΔt)⌉ (θ_N ≥ 2π closes the revolution)."""
    step = omega * sample_period
    return int(np.ceil(TWO_PI / step - 1e-9))


@dataclass(frozen=True)
class Commands:
    """Machining commands of one revolution (paper Eq. 15) and what they give the follower.

    Attributes:
        t: (N,) time of each command [s], k·Δt.
        theta: (N,) cam angle turned since the program start [rad], k·ω·Δt (≥ 0; the
            turning sense is ``sense``).
        seg: (N,) PH segment of each command (0-based; segment i runs from junction i to i+1).
        xi: (N,) curve parameter ξ ∈ [0, 1] in that segment.
        point: (N,) the command X_com + i·Y_com: the pitch-curve point r_i(ξ) in the cam frame.
        s_actual: (N,) follower displacement the command produces.
        s_desired: (N,) s(θ_k) of the motion program.
        sample_period: Δt [s].
        speed_rpm: cam speed [rpm].
        omega: cam speed [rad/s].
        sense: +1 ccw, −1 cw.
        iterations: Newton iterations of the vectorised sweep (the largest over all commands).
    """

    t: np.ndarray
    theta: np.ndarray
    seg: np.ndarray
    xi: np.ndarray
    point: np.ndarray
    s_actual: np.ndarray
    s_desired: np.ndarray
    sample_period: float
    speed_rpm: float
    omega: float
    sense: int
    iterations: int

    @property
    def n(self) -> int:
        return int(self.theta.shape[0])

    @property
    def x(self) -> np.ndarray:
        """X_com (paper Eq. 15), cam frame."""
        return self.point.real

    @property
    def y(self) -> np.ndarray:
        """Y_com (paper Eq. 15), cam frame."""
        return self.point.imag

    @property
    def deviation(self) -> np.ndarray:
        """s_actual − s_desired at every command."""
        return self.s_actual - self.s_desired

    @property
    def step_deg(self) -> float:
        """Cam rotation between commands [deg]."""
        return float(np.rad2deg(self.omega * self.sample_period))


class RotationalInterpolator:
    """Vectorised rotational interpolator of a PH pitch curve (paper §3.2).

    Args:
        pitch: the solved PH pitch curve (spline, junction angles, follower geometry).
    """

    def __init__(self, pitch: PitchCurve):
        self.pitch = pitch
        self.solver: FollowerLineSolver = pitch.solver()
        # the pitch curve as Bézier segments and the cam angles that bound them (PH: the
        # spline and its junction angles; B-spline: its knot spans in Bézier form)
        fol = pitch.follower
        ang = self.solver.angles
        self._h = np.diff(ang)                                   # junction spacing [rad]
        # dξ/dθ at both ends of every segment, from differentiating the contact condition
        # g(ξ, θ) = 0 (Eq. 13 for a translating follower: ξ' = δ·Y / Re(e^{iδθ}r')):
        #   g_ξ ξ' + g_θ = 0   →   ξ' = −g_θ / g_ξ.
        m = self.solver.spline.M
        seg = np.arange(m)
        slopes = []
        for x, a in ((0.0, ang[:-1]), (1.0, ang[1:])):
            q, dq, d2q = self._at(seg, np.full(m, x), a)
            _, g_xi, g_th = fol.contact_residual(q, dq, d2q)
            if np.any(g_xi == 0):
                k = int(np.argmax(g_xi == 0))
                raise SolveError(f"the follower touches the pitch curve tangentially at junction {k} "
                                 f"(cam angle {np.rad2deg(ang[k]):.4f}°): Eq. 13 has no simple root there")
            slopes.append(-g_th / g_xi * self._h)                # dξ/du (u = (θ−θ_i)/h_i)
        self._m0, self._m1 = slopes

    def _at(self, seg: np.ndarray, xi: np.ndarray, theta: np.ndarray):
        """q, q′, q″ of the chain at (seg, ξ), turned into the fixed frame at θ."""
        s = self.solver
        rot = np.exp(1j * s.sense * theta)
        d2 = s._dpc[:, 1:] * np.arange(1, s._deg)
        return (rot * horner(s._pc[seg], xi), rot * horner(s._dpc[seg], xi),
                rot * horner(d2[seg], xi) if d2.shape[1] else np.zeros(seg.shape, complex))

    def initial_guess(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(segment, ξ) starting values: cubic Hermite interpolation of ξ(θ) between the
        junctions, where ξ = 0, 1 and dξ/dθ are exact."""
        t = self.solver.wrap(theta)
        seg = self.solver.segment_of(t)
        u = (t - self.solver.angles[seg]) / self._h[seg]
        u2 = u * u
        u3 = u2 * u
        xi = (u3 - 2 * u2 + u) * self._m0[seg] + (-2 * u3 + 3 * u2) + (u3 - u2) * self._m1[seg]
        return seg, np.clip(xi, 0.0, 1.0)

    def solve(self, theta: np.ndarray) -> Contact:
        """Eq. 13 at every cam angle θ [rad] (any values; taken modulo 2π), in chunks of
        :data:`CHUNK` commands, each one vectorised Newton sweep.

        Raises:
            SolveError: a root is not bracketed by the segment the junction angles give
                (the follower line misses the curve there), or Newton fails; the message
                names the cam angle.
        """
        theta = np.asarray(theta, dtype=float).ravel()
        n = theta.shape[0]
        seg = np.empty(n, dtype=np.intp)
        xi = np.empty(n)
        pts = np.empty(n, dtype=complex)
        lift = np.empty(n)
        y: np.ndarray | None = np.empty(n)
        iterations = 0
        for lo in range(0, n, CHUNK):
            th = theta[lo:lo + CHUNK]
            s0, x0 = self.initial_guess(th)
            self._check_bracketed(th, s0)
            c = self.solver.solve(th, xi0=x0, seg=s0)
            seg[lo:lo + CHUNK] = c.seg
            xi[lo:lo + CHUNK] = c.xi
            pts[lo:lo + CHUNK] = c.point
            lift[lo:lo + CHUNK] = c.lift
            if c.Y is None:
                y = None
            elif y is not None:
                y[lo:lo + CHUNK] = c.Y
            iterations = max(iterations, c.iterations)
        return Contact(seg=seg, xi=xi, point=pts, Y=y, iterations=iterations, lift=lift)

    def _check_bracketed(self, theta: np.ndarray, seg: np.ndarray) -> None:
        """Eq. 13's residual must change sign over the segment (its ends are junctions):
        Re(e^{iδθ}q) − e at both ends for a translating follower, the kind's own residual else."""
        g0, g1, scale = self.solver.residual_ends(theta, seg)
        bad = (g0 * g1 > 0) & (np.abs(g0) > scale) & (np.abs(g1) > scale)
        if bad.any():
            k = int(np.argmax(bad))
            raise SolveError(
                f"the follower line does not cross PH segment {int(seg[k])} at cam angle "
                f"{np.rad2deg(np.mod(theta[k], TWO_PI)):.4f}° (Eq. 13 root not bracketed by its junctions)")

    def commands(self, speed_rpm: float, sample_period: float) -> Commands:
        """The N commands of one revolution at ``speed_rpm`` every ``sample_period`` seconds."""
        omega = speed_rpm * TWO_PI / 60.0
        n = command_count(omega, sample_period)
        if n > MAX_COMMANDS:
            raise SolveError(f"{n} commands per revolution exceed the limit of {MAX_COMMANDS}")
        k = np.arange(n)
        theta = k * (omega * sample_period)
        c = self.solve(theta)
        return Commands(t=k * sample_period, theta=theta, seg=c.seg, xi=c.xi, point=c.point,
                        s_actual=c.lift, s_desired=self.pitch.program.s(theta),
                        sample_period=float(sample_period), speed_rpm=float(speed_rpm), omega=float(omega),
                        sense=self.pitch.geometry.sense, iterations=c.iterations)

    def displacement(self, theta: np.ndarray) -> np.ndarray:
        """s_actual at any cam angles [rad]."""
        return self.solve(theta).lift


# ---- kinematics of the commanded motion --------------------------------------------
@dataclass(frozen=True)
class FiniteDifferences:
    """Velocity, acceleration and jerk of a sampled displacement (per second).

    Each value is attached to the cam angle at the centre of its stencil
    (``*_theta`` [rad]), so curves can be compared with the exact derivatives.
    """

    scheme: str
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    v_theta: np.ndarray
    a_theta: np.ndarray
    j_theta: np.ndarray


def finite_differences(s: np.ndarray, dt: float, omega: float, theta0: float, scheme: str,
                       pad: tuple[int, int] = (3, 2)) -> FiniteDifferences:
    """Derivatives of samples s_k = s(θ₀ + kωΔt) that include ``pad`` extra samples before
    and after the N samples of interest; returns N values of each derivative.

    ``backward`` (what a controller computes from past commands; the paper's Figs 4–8):
        v_k = ∇s_k/Δt,  a_k = ∇²s_k/Δt²,  j_k = ∇³s_k/Δt³, stencil centres at
        k − ½, k − 1, k − 3/2;
    ``central``: v_k = (s_{k+1} − s_{k−1})/2Δt, a_k = (s_{k+1} − 2s_k + s_{k−1})/Δt²,
        j_k = (s_{k+2} − 2s_{k+1} + 2s_{k−1} − s_{k−2})/2Δt³, centred at k.
    Both are exact for cubics; they differ where the jerk jumps (the start and end of a
    rise, junctions of the spline), which is where the maximum jerk is found.
    """
    before, after = pad
    n = s.shape[0] - before - after
    k = np.arange(n)
    i = k + before
    step = omega * dt

    def at(offset: int) -> np.ndarray:
        return s[i + offset]

    if scheme == "backward":
        v = (at(0) - at(-1)) / dt
        a = (at(0) - 2 * at(-1) + at(-2)) / dt**2
        j = (at(0) - 3 * at(-1) + 3 * at(-2) - at(-3)) / dt**3
        centres = (0.5, 1.0, 1.5)
    elif scheme == "central":
        v = (at(1) - at(-1)) / (2 * dt)
        a = (at(1) - 2 * at(0) + at(-1)) / dt**2
        j = (at(2) - 2 * at(1) + 2 * at(-1) - at(-2)) / (2 * dt**3)
        centres = (0.0, 0.0, 0.0)
    else:
        raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
    th = theta0 + k * step
    return FiniteDifferences(scheme, v, a, j, th - centres[0] * step, th - centres[1] * step,
                             th - centres[2] * step)


@dataclass(frozen=True)
class InterpolatorAccuracy:
    """What the commands give the follower, against the design intent (paper Table 2).

    Attributes:
        commands: the commands of one revolution.
        differences: finite-difference kinematics of s_actual, one per scheme.
        desired: exact maxima of |v|, |a|, |j| of the motion program (dense, closed forms).
        desired_differences: the same finite differences applied to the exact s(θ_k)
            (shows what differencing alone does to the maxima).
    """

    commands: Commands
    differences: dict[str, FiniteDifferences]
    desired: dict[str, float]
    desired_differences: dict[str, FiniteDifferences] = field(repr=False)

    @property
    def max_deviation(self) -> tuple[float, float]:
        """(max |s_actual − s| over the commands, cam angle [deg] where it occurs)."""
        dev = self.commands.deviation
        k = int(np.argmax(np.abs(dev)))
        return float(abs(dev[k])), float(np.rad2deg(self.commands.theta[k]))

    def maxima(self, scheme: str = DEFAULT_SCHEME) -> dict[str, tuple[float, float]]:
        """{"velocity"|"acceleration"|"jerk": (max |value|, cam angle [deg] of its stencil centre)}."""
        fd = self.differences[scheme]
        out = {}
        for name, val, th in (("velocity", fd.v, fd.v_theta), ("acceleration", fd.a, fd.a_theta),
                              ("jerk", fd.j, fd.j_theta)):
            k = int(np.argmax(np.abs(val)))
            out[name] = (float(abs(val[k])), float(np.rad2deg(th[k]) % 360.0))
        return out

    def summary(self, scheme: str = DEFAULT_SCHEME) -> dict[str, Any]:
        """The ``interpolator`` section of report.json (lengths in spec units, angles in
        degrees, time in s)."""
        c = self.commands
        dev, at = self.max_deviation
        out: dict[str, Any] = {
            "speed_rpm": c.speed_rpm,
            "sample_period": c.sample_period,
            "step_deg": c.step_deg,
            "commands": c.n,
            "direction": "ccw" if c.sense > 0 else "cw",
            "newton_iterations": c.iterations,
            "max_deviation": dev,
            "max_deviation_at_deg": at,
            "differencing": scheme,
            "warning": None,
        }
        if c.step_deg > COARSE_STEP_DEG:
            out["warning"] = (f"{c.step_deg:.4g}° of cam rotation per command: the commands and their finite "
                              "differences do not resolve the motion; use a shorter machining.sample_period "
                              "or a lower machining.rotary_speed_rpm")
        mx = self.maxima(scheme)
        for name in ("velocity", "acceleration", "jerk"):
            value, where = mx[name]
            want = self.desired[name]
            out[name] = {"max": value, "at_deg": where, "desired_max": want,
                         "increase_percent": 100.0 * (value - want) / want if want > 0 else None}
        out["schemes"] = {
            s: {name: self.maxima(s)[name][0] for name in ("velocity", "acceleration", "jerk")}
            for s in SCHEMES}
        out["schemes_on_desired_motion"] = {
            s: {"velocity": float(np.max(np.abs(fd.v))), "acceleration": float(np.max(np.abs(fd.a))),
                "jerk": float(np.max(np.abs(fd.j)))}
            for s, fd in self.desired_differences.items()}
        return out


def interpolate(pitch: PitchCurve, speed_rpm: float, sample_period: float) -> Commands:
    """The commands of one revolution (see :class:`RotationalInterpolator`)."""
    return RotationalInterpolator(pitch).commands(speed_rpm, sample_period)


def interpolator_accuracy(pitch: PitchCurve, speed_rpm: float, sample_period: float
                          ) -> InterpolatorAccuracy:
    """Commands of one revolution and the follower motion they produce: deviation from
    s(θ) and finite-difference v, a, j (both schemes) against the exact maxima."""
    interp = RotationalInterpolator(pitch)
    cmds = interp.commands(speed_rpm, sample_period)
    before, after = 3, 2
    step = cmds.omega * sample_period
    th_pad = np.concatenate([np.arange(-before, 0), np.arange(cmds.n, cmds.n + after)]) * step
    s_ends = interp.displacement(th_pad)
    s_pad = np.concatenate([s_ends[:before], cmds.s_actual, s_ends[before:]])
    sd_pad = pitch.program.s(np.arange(-before, cmds.n + after) * step)
    diffs = {s: finite_differences(s_pad, sample_period, cmds.omega, 0.0, s) for s in SCHEMES}
    ddiffs = {s: finite_differences(sd_pad, sample_period, cmds.omega, 0.0, s) for s in SCHEMES}
    return InterpolatorAccuracy(cmds, diffs, pitch.program.maxima(cmds.omega), ddiffs)
