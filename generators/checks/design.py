"""Design checks of a cam and its follower (thesis Ch. 3, §5.3), for every follower kind.

Everything is evaluated on the design intent — the motion program s(θ) and the follower
(:mod:`cam_workbench.generators.followers`) — vectorised over sample angles.  The formulas below are the
translating follower's (the thesis'); the follower interface gives each kind's own (the
oscillating arm's pressure angle against the velocity perpendicular to the arm, its force from
the torque about the pivot, a flat face's φ and ρ):

=================  ==========================================================  ============
check              quantity                                                    passes when
=================  ==========================================================  ============
pressure_angle     φ = atan((s′ − e)/(s₀ + s))  (thesis Eq. 3.4)               max |φ| ≤ limit
separation         F = (P_L + k·s + M_f·s″ω²)/cos φ  (Eq. 3.5, with a spring)  min F > limit
oscillation        s′ in the direction of travel (rise ↑, return ↓) (§3.3)     min ≥ 0
contact_stress     S² = F(1/r_f + 1/ρ_c)/(π t Δ), Δ = Σ(1 − ν²)/E  (Eq. 3.6)  max S ≤ S_d
curvature          convex pitch radius ρ (Eq. 3.7) ≥ factor · r_f  (Eq. 5.7)   min ≥ limit
undercut           convex profile radius ρ − r_f > 0 and the roller envelope    min > 0
                   does not cross itself
cusp (flat)        profile radius ρ = R_b + s + s″ (oscillating: h + h_γγ)      min > 0
face_width (flat)  face width the contact needs, centred on stem / arm_length  ≤ face_width
=================  ==========================================================  ============

A check that cannot be decided is "skipped", never "pass": no load to check, a positive drive, or no
limit given (``material.allowable_stress``, ``follower.face_width``: the value is reported, the note
names the field; :mod:`cam_workbench.generators.checks.status`).

ρ_c = ρ − r_f is the cam surface's signed radius of curvature (+ convex, − concave), so the
same Eq. 3.6 covers convex and concave contact (the thesis put the pitch radius ρ there;
:func:`~cam_workbench.generators.followers.load.hertz_stress` takes whichever radius it is given; a flat face is a cylinder on a plane).

Units are the spec's (:mod:`cam_workbench.generators.followers.load`); an oscillating follower's lifts and
reduced kinematics are in degrees of arm rotation.

For an optimiser, :func:`constraint_arrays` gives every constraint as a normalised array
g ≤ 0 over all sample points (thesis Eq. 5.2–5.13 in a smooth form).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..followers import force_reference
from ..followers.base import Follower
from ..kinds import body_of, follower_of
from ..motion.segments import MATCHING_LAWS
from .buildability import _segments_intersect
from ..motion.program import Kinematics, MotionProgram
from ..spec.model import CamSpec
from .status import NO_LIMIT, limited_status
from .transmission import linkage_checks

TWO_PI = 2.0 * np.pi
THESIS_NODES = 71

UNIT_LABELS = {
    "mm": {"length": "mm", "force": "N", "stress": "MPa", "reduced_velocity": "mm/rad",
           "reduced_acceleration": "mm/rad²", "reduced_jerk": "mm/rad³"},
    "in": {"length": "in", "force": "lbf", "stress": "psi", "reduced_velocity": "in/rad",
           "reduced_acceleration": "in/rad²", "reduced_jerk": "in/rad³"},
}


# ---- sample angles ----------------------------------------------------------------------
@dataclass(frozen=True)
class CheckSamples:
    """Cam angles where the checks are evaluated, each tagged with its motion segment
    (segment ends are evaluated one-sidedly with their own segment's law)."""

    theta: np.ndarray        # [rad], within [0, 2π]
    segment: np.ndarray      # motion segment index of each sample
    is_end: np.ndarray       # True at the first and last sample of a segment


def check_samples(program: MotionProgram, sampling: str = "dense", samples: int = 1001) -> CheckSamples:
    """Sample angles: per rise/return ``samples`` equally spaced θ (dense) or the thesis' 71
    nodes (70 equal intervals of the B-spline parameter u, thesis §5.3; of θ for a closed-form
    law); per dwell its two ends (every quantity is constant there)."""
    th, seg, end = [], [], []
    for k in range(len(program.starts)):
        a, b = program.starts[k], program.starts[k] + program.spans[k]
        curve = program.curves[k] if program.curves else None
        if program.laws[k] is None:
            t = np.array([a, b])
        elif sampling == "thesis71":
            if curve is not None:
                t = a + curve.theta_at(curve.node_parameters(THESIS_NODES))
                t[0], t[-1] = a, b
            else:
                t = np.linspace(a, b, THESIS_NODES)
        else:
            t = np.linspace(a, b, samples)
        e = np.zeros(t.shape, dtype=bool)
        e[0] = e[-1] = True
        th.append(t)
        seg.append(np.full(t.shape, k))
        end.append(e)
    return CheckSamples(np.concatenate(th), np.concatenate(seg), np.concatenate(end))


# ---- the physics, vectorised ------------------------------------------------------------
@dataclass(frozen=True)
class CamState:
    """Every checked quantity at a set of cam angles (arrays of equal length)."""

    theta: np.ndarray
    segment: np.ndarray
    kin: Kinematics
    pressure_angle: np.ndarray     # φ [rad], signed
    force: np.ndarray              # F, force unit
    pitch_radius: np.ndarray       # ρ of the pitch curve (Eq. 3.7), + convex
    profile_radius: np.ndarray     # ρ − r_f: the cam surface, + convex
    stress: np.ndarray             # Hertz S, stress unit
    travel_velocity: np.ndarray    # s′ in the segment's direction of travel (+ for rise/return)


class StateModel:
    """The spec's numbers the checks need, and :meth:`state` that evaluates them at any θ
    through the follower's interface (:class:`cam_workbench.generators.followers.base.Follower`)."""

    def __init__(self, spec: CamSpec, program: MotionProgram | None = None, follower: Follower | None = None):
        self.spec = spec
        self.program = program or MotionProgram.from_spec(spec)
        #: the follower (roller) whose contact with its cam is checked: the spec's own, or the
        #: second roller of a conjugate pair
        self.follower: Follower = follower or follower_of(spec)
        self.omega = spec.cam.speed_rpm * TWO_PI / 60.0
        fol = spec.follower
        width = fol.roller_width if spec.is_roller else None
        self.contact_length = min(spec.cam.thickness, width or spec.cam.thickness)
        mat = spec.material
        self.moduli = (mat.modulus("cam", spec.units), mat.cam_poisson,
                       mat.modulus("follower", spec.units), mat.follower_poisson)
        self.direction = np.sign(self.program.lifts)
        #: a groove or a conjugate pair holds the follower both ways: no separation, and where the
        #: contact force changes sign the other wall (the other cam) takes the load
        self.body = body_of(spec)
        self.form_closed = self.body.closure == "form"

    @property
    def geometry(self) -> Follower:
        """The follower (the name before the follower interface)."""
        return self.follower

    @property
    def has_load(self) -> bool:
        return self.follower.has_load

    def state(self, theta: np.ndarray, segment: np.ndarray | None = None) -> CamState:
        theta = np.asarray(theta, dtype=float)
        seg = self.program.segment_of(theta) if segment is None else np.asarray(segment)
        k = self.program.evaluate(theta, seg)
        fol = self.follower
        phi, rho = fol.kinematic_state(k)
        force = fol.contact_force(k, self.omega, phi)
        prof = rho - fol.profile_offset
        stress = fol.contact_stress(force, k, self.contact_length, self.moduli, rho)
        if self.form_closed:
            # a negative force is taken by the other side: the groove's outer wall, or the other cam
            other = self.body.reverse_contact_stress(self, force, rho)
            stress = np.where(force >= 0, stress, other)
        return CamState(theta, seg, k, phi, force, rho, prof, stress, k.ds * self.direction[seg])


# ---- results -------------------------------------------------------------------------------
@dataclass(frozen=True)
class CheckResult:
    """One design check: the extreme value, where it occurs, the limit and the verdict."""

    name: str
    description: str
    kind: str                  # "max" or "min": which extreme is checked
    value: float | None
    at_deg: float | None
    limit: float | None
    unit: str
    status: str                # "pass", "fail" or "skipped"
    note: str = ""

    @property
    def passed(self) -> bool:
        return self.status != "fail"

    def to_dict(self) -> dict[str, Any]:
        return {"description": self.description, "kind": self.kind, "value": self.value,
                "at_deg": self.at_deg, "limit": self.limit, "unit": self.unit,
                "status": self.status, "passed": self.passed, "note": self.note}


@dataclass(frozen=True)
class DesignChecks:
    """All check results, plus the extremes of force, stress and reduced motion (the thesis'
    "Maximum Values" tables) and how they were sampled."""

    results: tuple[CheckResult, ...]
    extremes: dict[str, dict[str, float]]
    sampling: str
    samples: int
    units: str
    state: CamState = field(repr=False)

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.results)

    @property
    def failed(self) -> list[str]:
        return [r.name for r in self.results if r.status == "fail"]

    def __getitem__(self, name: str) -> CheckResult:
        for r in self.results:
            if r.name == name:
                return r
        raise KeyError(name)

    def to_dict(self) -> dict[str, Any]:
        """The ``checks`` section of report.json."""
        return {
            "passed": self.passed,
            "failed": self.failed,
            "sampling": self.sampling,
            "samples_per_segment": self.samples,
            "points": int(self.state.theta.shape[0]),
            "results": {r.name: r.to_dict() for r in self.results},
            "extremes": self.extremes,
        }


def _deg(theta: float) -> float:
    d = float(np.rad2deg(theta)) % 360.0
    return 0.0 if abs(d - 360.0) < 1e-9 else d


def _extreme(values: np.ndarray, st: CamState, model: StateModel, pick: Callable[[CamState], np.ndarray],
             refine: bool, mask: np.ndarray | None = None) -> tuple[float, float, int]:
    """(max of ``values`` over the samples (optionally masked), θ [rad] where it occurs, its
    motion segment), refined by golden section inside that segment when ``refine``
    (``pick`` gives the same quantity from a :class:`CamState`)."""
    v = np.where(mask, values, -np.inf) if mask is not None else values
    v = np.where(np.isnan(v), -np.inf, v)
    j = int(np.argmax(v))
    seg = int(st.segment[j])
    if not np.isfinite(v[j]) or not refine:
        return float(v[j]), float(st.theta[j]), seg
    in_seg = st.segment == seg
    if mask is not None:
        in_seg &= mask
    if np.count_nonzero(in_seg) < 3:
        return float(v[j]), float(st.theta[j]), seg

    def f(t: np.ndarray) -> np.ndarray:
        out = pick(model.state(t, np.full(t.shape, seg)))
        return np.where(np.isnan(out), -np.inf, out)

    x, val = refine_max_zoom(f, st.theta[in_seg], v[in_seg])
    return float(val), float(x), seg


def refine_max_zoom(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, values: np.ndarray,
                    rounds: int = 4, points: int = 33) -> tuple[float, float]:
    """(x*, f(x*)) maximising ``f`` between the neighbours of the best sample: ``rounds``
    vectorised re-samplings with ``points`` points each, every round zooming onto the
    neighbours of its best point (the interval shrinks 16× per round; one call of ``f``
    per round, which matters when f inverts a B-spline)."""
    k = int(np.argmax(values))
    best_x, best_v = float(x[k]), float(values[k])
    lo, hi = x[max(k - 1, 0)], x[min(k + 1, len(x) - 1)]
    for _ in range(rounds):
        t = np.linspace(lo, hi, points)
        v = f(t)
        j = int(np.argmax(v))
        if v[j] > best_v:
            best_x, best_v = float(t[j]), float(v[j])
        lo, hi = t[max(j - 1, 0)], t[min(j + 1, points - 1)]
    return best_x, best_v


def run_checks(spec: CamSpec, *, sampling: str | None = None, samples: int | None = None,
               program: MotionProgram | None = None, follower: Follower | None = None) -> DesignChecks:
    """Evaluate every design check of ``spec`` (``[checks]`` gives the limits and sampling;
    ``sampling``/``samples`` override it).

    A body with more than one cam (a conjugate pair) adds the checks of each further roller on
    its cam — pressure angle, contact stress, curvature, undercut — named with the cam's suffix
    (``pressure_angle_cam2``, …: :data:`CAM_SUFFIXES`).  ``follower``: check that follower alone
    (the body's further cams are then not added)."""
    cfg = spec.checks
    sampling = sampling or cfg.sampling
    samples = samples or cfg.samples
    refine = sampling == "dense"
    model = StateModel(spec, program, follower)
    cs = check_samples(model.program, sampling, samples)
    st = model.state(cs.theta, cs.segment)
    u = spec.units
    fol = model.follower
    lab = unit_labels(u, fol.lift_unit)
    results: list[CheckResult] = []
    moving = np.array([model.program.laws[s] is not None for s in st.segment])

    # pressure angle (Eq. 3.4, 5.5)
    v, t, sg = _extreme(np.abs(st.pressure_angle), st, model, lambda s: np.abs(s.pressure_angle), refine)
    phi_deg = float(np.rad2deg(v))
    signed = float(np.rad2deg(model.state(np.array([t]), np.array([sg])).pressure_angle[0]))
    results.append(CheckResult(
        "pressure_angle", "largest |pressure angle| (thesis Eq. 3.4)", "max", phi_deg, _deg(t),
        cfg.max_pressure_angle, "deg", "pass" if phi_deg <= cfg.max_pressure_angle else "fail",
        f"signed {signed:.4g}°"))

    # separation (Eq. 3.5, 5.10)
    if model.form_closed:
        results.append(CheckResult(
            "separation", "smallest driving force (thesis Eq. 3.5, with the spring rate)", "min",
            None, None, cfg.min_force, lab["force"], "skipped",
            "positive drive: the groove holds the roller both ways (report.json body.drive: which wall drives where)"))
    elif model.has_load:
        v, t, _ = _extreme(-st.force, st, model, lambda s: -s.force, refine)
        fmin = -v
        results.append(CheckResult(
            "separation", "smallest driving force (thesis Eq. 3.5, with the spring rate)", "min",
            fmin, _deg(t), cfg.min_force, lab["force"], "pass" if fmin > cfg.min_force else "fail"))
    else:
        loads = ("preload_torque, arm_inertia and spring_torque_rate" if fol.pivoted
                 else "preload, mass and spring_rate")
        results.append(CheckResult(
            "separation", "smallest driving force (thesis Eq. 3.5, with the spring rate)", "min",
            None, None, cfg.min_force, lab["force"], "skipped",
            f"follower.{loads} are all 0: no load to check"))

    # oscillation (§3.3, Eq. 5.2/5.4): interior of every rise/return
    interior = moving & ~cs.is_end
    if interior.any():
        v, t, _ = _extreme(-st.travel_velocity, st, model, lambda s: -s.travel_velocity, refine, interior)
        vmin = -v
        tol = 1e-12 * max(1.0, float(np.max(np.abs(st.kin.ds))))
        results.append(CheckResult(
            "oscillation", "smallest reduced velocity in the direction of travel (rise ↑, return ↓)",
            "min", vmin, _deg(t), 0.0, lab["reduced_velocity"], "pass" if vmin >= -tol else "fail"))

    # continuity at the segment junctions (the laws' promises, checks.min_continuity)
    cont = continuity_check(model.program, cfg.min_continuity, lab)
    if cont is not None:
        results.append(cont)
    # the linkage to the tool ([linkage]): the four-bar's transmission angle
    results.extend(CheckResult(**r) for r in linkage_checks(spec, model.program, cs.theta, cs.segment))

    # contact stress (Eq. 3.6, 5.13)
    if fol.has_contact_stress and model.has_load:
        v, t, _ = _extreme(st.stress, st, model, lambda s: s.stress, refine)
        lim = spec.material.allowable_stress
        results.append(CheckResult(
            "contact_stress", "largest Hertz contact stress (thesis Eq. 3.6; convex and concave)",
            "max", v, _deg(t), lim, lab["stress"], limited_status(v <= lim if lim is not None else None),
            "" if lim is not None else NO_LIMIT.format(field="material.allowable_stress")))
    else:
        results.append(CheckResult(
            "contact_stress", "largest Hertz contact stress (thesis Eq. 3.6; convex and concave)",
            "max", None, None, spec.material.allowable_stress, lab["stress"], "skipped",
            f"{fol.contact_words} follower" if not fol.has_contact_stress else "no follower load given"))

    if fol.design_curve == "profile":
        results.extend(_flat_face_checks(model, st, refine, cfg, lab))
    else:
        results.extend(_pitch_curvature_checks(spec, model, st, cs, refine, cfg, lab))
    extremes = _extremes(st, model, refine, lab)
    if follower is None:
        for suffix, other in model.body.further_followers(spec):
            sub = run_checks(spec, sampling=sampling, samples=samples, program=model.program, follower=other)
            for r in sub.results:
                if r.name in PER_CAM_CHECKS:
                    results.append(dataclasses.replace(r, name=f"{r.name}_{suffix}",
                                                       description=f"{CAM_SUFFIXES[suffix]}: {r.description}"))
            extremes.update({f"{k}_{suffix}": v for k, v in sub.extremes.items() if k in PER_CAM_EXTREMES})
    return DesignChecks(tuple(results), extremes, sampling, samples if sampling == "dense" else THESIS_NODES,
                        u, st)


ORDER_WORDS = {-1: "position", 0: "velocity", 1: "acceleration", 2: "jerk"}
_DERIVATIVE_UNITS = ("length", "reduced_velocity", "reduced_acceleration", "reduced_jerk")


def junction_text(j: Any, program: MotionProgram, lab: dict[str, str], required: int | None = None) -> str:
    """One line about a junction: where, which segments, the first jump and the promise, e.g.
    ``motion[0] → motion[1] (constant_velocity) at 60°: velocity jumps by 7.639 mm/rad (0 → 7.639);
    constant_velocity promises C2``."""
    names = (lambda k: program.laws[k] or "dwell")
    head = f"motion[{j.left}] ({names(j.left)}) → motion[{j.right}] ({names(j.right)}) at {j.at_deg:.4g}°"
    if j.order >= 3:
        return f"{head}: C3 (s, s′, s″, s‴ continuous)"
    n = j.order + 1
    unit = lab["lift"] if n == 0 else lab[_DERIVATIVE_UNITS[n]]
    text = (f"{head}: {ORDER_WORDS[j.order]} jumps by {_g(j.jumps[n])} {unit} "
            f"({_g(j.values_left[n])} → {_g(j.values_right[n])}); C{max(j.order, 0)}")
    req = j.promised if required is None else required
    if j.order < j.promised:
        # the sides whose promise is the junction's (a dwell promises C3: no limit of its own)
        who = list(dict.fromkeys(program.laws[k] or "a dwell" for k, e in ((j.left, 1), (j.right, 0))
                                 if program.promise(k)[e] == j.promised))
        text += f", but {' and '.join(who)} promise{'s' if len(who) == 1 else ''} C{j.promised}"
    elif j.order < req:
        text += f", below checks.min_continuity = {req}"
    return text


def _g(v: float) -> str:
    t = f"{v:.4g}"
    return "0" if t == "-0" else t


def continuity_check(program: MotionProgram, min_continuity: int | None, lab: dict[str, str]
                     ) -> CheckResult | None:
    """The order of continuity reached at every segment junction against the order the laws on
    either side promise (and ``checks.min_continuity``).  Reported when it can fail: when the
    program has a law solved from boundary conditions or fitted, or ``min_continuity`` is given
    (dwell-to-dwell closed-form and B-spline laws meet their promises by construction)."""
    junctions = program.junctions()
    required = [max(j.promised, min_continuity if min_continuity is not None else -1) for j in junctions]
    short = [(j, r) for j, r in zip(junctions, required) if j.order < r]
    if not short and min_continuity is None and not any(law in MATCHING_LAWS for law in program.laws):
        return None
    worst, req = min(zip(junctions, required), key=lambda jr: (jr[0].order - jr[1], jr[0].index))
    if short:
        note = "; ".join(junction_text(j, program, lab, r) for j, r in short[:3])
        if len(short) > 3:
            note += f"; and {len(short) - 3} more junctions"
    else:
        note = f"lowest: {junction_text(worst, program, lab, req)}"
    return CheckResult(
        "continuity", "lowest order of continuity at a segment junction (0 position, 1 velocity, 2 acceleration, "
        "3 jerk continuous) against what the laws there promise", "min", float(worst.order), worst.at_deg % 360.0,
        float(req), "", "fail" if short else "pass", note)


#: the suffix of a further cam's check names → the cam in words
CAM_SUFFIXES = {"cam2": "second cam"}
#: the checks each cam of a body has of its own (the others — separation, oscillation — are the motion's)
PER_CAM_CHECKS = ("pressure_angle", "contact_stress", "curvature", "convexity", "undercut")
#: the extremes each cam has of its own
PER_CAM_EXTREMES = ("force", "pressure_angle", "contact_stress", "min_concave_pitch_radius")


def base_check_name(name: str) -> str:
    """A check's name without a further cam's suffix (``undercut_cam2`` → ``undercut``)."""
    for suffix in CAM_SUFFIXES:
        if name.endswith("_" + suffix):
            return name[: -len(suffix) - 1]
    return name


def _pitch_curvature_checks(spec: CamSpec, model: StateModel, st: CamState, cs: CheckSamples, refine: bool,
                            cfg: Any, lab: dict[str, str]) -> list[CheckResult]:
    """Knife edge and roller: the curvature with the safety factor (Eq. 3.7, 5.7), the convexity
    option and the true undercut of the roller envelope."""
    results: list[CheckResult] = []
    rr = model.follower.profile_offset
    convex = st.pitch_radius > 0
    v, t, _ = _extreme(-np.where(convex, st.pitch_radius, np.inf), st, model,
                    lambda s: -np.where(s.pitch_radius > 0, s.pitch_radius, np.inf), refine)
    rho_min = -v
    lim = cfg.undercut_factor * rr
    results.append(CheckResult(
        "curvature", f"smallest convex pitch radius of curvature (thesis Eq. 3.7) ≥ "
        f"{cfg.undercut_factor:g} × roller radius", "min", _finite(rho_min), _deg(t), lim,
        lab["length"], "pass" if rho_min >= lim else "fail"))
    if cfg.convex:
        v, t, _ = _extreme(-1.0 / st.pitch_radius, st, model, lambda s: -1.0 / s.pitch_radius, refine)
        kmin = -v
        results.append(CheckResult(
            "convexity", "smallest pitch-curve curvature κ = 1/ρ (checks.convex: thesis Eq. 5.7 with signed ρ)",
            "min", kmin, _deg(t), 0.0, "1/" + lab["length"], "pass" if kmin >= 0 else "fail"))
    if spec.is_roller:
        crossing = envelope_crossing(model, cs)
        ok = rho_min - rr > 0 and crossing is None
        note = "" if crossing is None else f"the roller envelope crosses itself near {crossing:.2f}°"
        results.append(CheckResult(
            "undercut", "smallest convex cam-surface radius of curvature ρ − r_f (the roller envelope)",
            "min", _finite(rho_min - rr), _deg(t) if crossing is None else crossing, 0.0,
            lab["length"], "pass" if ok else "fail", note))
    return results


def _flat_face_checks(model: StateModel, st: CamState, refine: bool, cfg: Any, lab: dict[str, str]
                      ) -> list[CheckResult]:
    """Flat face: no cusp (the profile's radius of curvature ρ = R_b + s + s″ for the translating
    face, h + h_γγ for the oscillating one, must stay > 0), the convexity option, and the face width
    the contact needs against ``follower.face_width``."""
    fol = model.follower
    results: list[CheckResult] = []
    v, t, _ = _extreme(-st.pitch_radius, st, model, lambda s: -s.pitch_radius, refine)
    rho_min = -v
    formula = fol.cusp_formula
    results.append(CheckResult(
        "cusp", f"smallest radius of curvature of the profile ρ = {formula} (a flat face needs ρ > 0)",
        "min", _finite(rho_min), _deg(t), 0.0, lab["length"], "pass" if rho_min > 0 else "fail",
        "" if rho_min > 0 else "the face's envelope has a cusp: a larger base radius or a gentler motion"))
    if model.spec.checks.convex:
        v, t, _ = _extreme(-1.0 / st.pitch_radius, st, model, lambda s: -1.0 / s.pitch_radius, refine)
        results.append(CheckResult(
            "convexity", "smallest profile curvature κ = 1/ρ (checks.convex)", "min", -v, _deg(t), 0.0,
            "1/" + lab["length"], "pass" if -v >= 0 else "fail"))
    width, lo, hi, at = face_width_needed(model, st)
    limit = model.spec.follower.face_width
    centre = fol.face_centre
    note = (f"contact from {lo:.4g} to {hi:.4g} along the face from the "
            f"{fol.face_origin}")
    if limit is None:
        note += "; " + NO_LIMIT.format(field="follower.face_width")
    elif centre is None:
        note += "; the face centred on the contact's travel (follower.arm_length not given)"
    results.append(CheckResult(
        "face_width", "width of face the contact needs (centred on the stem / on arm_length)", "max", width, at,
        limit, lab["length"], limited_status(width <= limit if limit is not None else None), note))
    return results


def face_width_needed(model: StateModel, st: CamState) -> tuple[float, float, float, float]:
    """(width of a face centred on its reference that holds every contact, the contact's least
    and largest position along the face, the cam angle [deg] of the farthest contact): the
    positions over the check samples, refined at their extremes."""
    fol = model.follower
    pos = fol.face_position(st.kin)
    centre = fol.face_centre
    if centre is None:
        centre = 0.5 * (float(np.min(pos)) + float(np.max(pos)))
    v_hi, t_hi, _ = _extreme(pos, st, model, lambda s: fol.face_position(s.kin), refine=True)
    v_lo, t_lo, _ = _extreme(-pos, st, model, lambda s: -fol.face_position(s.kin), refine=True)
    lo, hi = -v_lo, v_hi
    if hi - centre >= centre - lo:
        return 2 * (hi - centre), lo, hi, _deg(t_hi)
    return 2 * (centre - lo), lo, hi, _deg(t_lo)


def unit_labels(units: str, lift_unit: str = "length") -> dict[str, str]:
    """Unit labels of the checks: :data:`UNIT_LABELS` with the reduced kinematics in the lift's
    unit (deg/rad, … for an oscillating follower's arm)."""
    lab = dict(UNIT_LABELS[units])
    if lift_unit == "angle":
        lab.update(lift="deg", reduced_velocity="deg/rad", reduced_acceleration="deg/rad²",
                   reduced_jerk="deg/rad³")
    else:
        lab["lift"] = lab["length"]
    return lab


def format_value(v: float | None, unit: str) -> str:
    """A check value with its unit as the check table prints it: degrees to 0.001°, other
    values to four decimals (four significant digits when very large or small); None is "—"."""
    if v is None:
        return "—"
    if unit == "deg":
        return f"{v:.3f}°"
    a = abs(v)
    text = f"{v:.4g}" if (a >= 1e5 or (a < 1e-3 and a != 0)) else f"{v:.4f}".rstrip("0").rstrip(".")
    return f"{text} {unit}"


#: min checks that pass only strictly above their limit (the others pass at the limit itself)
STRICT_MIN_CHECKS = frozenset({"separation", "undercut"})


def limit_sign(name: str, kind: str) -> str:
    """The comparison a check's value must satisfy against its limit, as printed before the
    limit: "≤" for a "max" check, ">" for the strict min checks (separation: F > min_force;
    undercut: ρ − r_f > 0), "≥" for the other min checks (oscillation, curvature, convexity)."""
    if kind == "max":
        return "≤"
    return ">" if base_check_name(name) in STRICT_MIN_CHECKS else "≥"


def _finite(v: float) -> float | None:
    return float(v) if np.isfinite(v) else None


def _extremes(st: CamState, model: StateModel, refine: bool, lab: dict[str, str]) -> dict[str, dict[str, Any]]:
    """Largest |value| (reported signed) of force, pressure angle, stress and the reduced
    velocity, acceleration and jerk — the thesis' "Maximum Values" table."""
    out: dict[str, dict[str, Any]] = {}
    items: list[tuple[str, Callable[[CamState], np.ndarray], str, float]] = [
        ("force", lambda s: s.force, lab["force"], 1.0),
        ("pressure_angle", lambda s: s.pressure_angle, "deg", float(np.rad2deg(1.0))),
        ("contact_stress", lambda s: s.stress, lab["stress"], 1.0),
        ("reduced_velocity", lambda s: s.kin.ds, lab["reduced_velocity"], 1.0),
        ("reduced_acceleration", lambda s: s.kin.d2s, lab["reduced_acceleration"], 1.0),
        ("reduced_jerk", lambda s: s.kin.d3s, lab["reduced_jerk"], 1.0),
    ]
    if not model.has_load:
        items = [it for it in items if it[0] not in ("force", "contact_stress")]
    for name, pick, unit, scale in items:
        vals = pick(st)
        if not np.any(np.isfinite(vals)):
            continue
        mag = np.where(np.isfinite(vals), np.abs(vals), -np.inf)
        _, t, sg = _extreme(mag, st, model, lambda s, p=pick: np.abs(p(s)), refine)
        val = float(pick(model.state(np.array([t]), np.array([sg])))[0])
        out[name] = {"value": val * scale, "at_deg": _deg(t), "unit": unit}
    rho = st.pitch_radius
    if np.any(rho < 0):
        j = int(np.argmax(np.where(rho < 0, rho, -np.inf)))
        out["min_concave_pitch_radius"] = {"value": float(-rho[j]), "at_deg": _deg(st.theta[j]),
                                           "unit": lab["length"]}
    return out


def envelope_crossing(model: StateModel, cs: CheckSamples, per_segment: int = 2001) -> float | None:
    """Cam angle [deg] where the roller envelope (the design-intent profile, pitch point
    moved by r_f along the inward normal) crosses itself, or None.  A profile whose polar
    angle is monotonic cannot cross itself; otherwise every pair of edges of the sampled
    polygon is tested."""
    prog = model.program
    th = np.concatenate([prog.starts[k] + prog.spans[k] * np.linspace(0, 1, per_segment if prog.laws[k] else 64,
                                                                        endpoint=False)
                         for k in range(len(prog.starts))])
    pts = envelope_points(model, th)
    dang = np.angle(np.roll(pts, -1) / pts)
    if np.all(dang > 0) or np.all(dang < 0):
        return None
    hit = _segments_intersect(pts, np.roll(pts, -1))
    return None if hit is None else _deg(th[hit[0]])


def envelope_points(model: StateModel, theta: np.ndarray) -> np.ndarray:
    """Design-intent cam profile points (complex, cam frame): the pitch point P(θ) moved by
    the roller radius along the pitch curve's normal towards the cam."""
    fol = model.follower
    k = model.program.evaluate(theta)
    p, d = fol.derivatives(theta, k, 1)
    # a ccw cam's pitch curve runs clockwise (the cam on its right), a cw cam's counter-clockwise
    inward = -1j * fol.sense * d / np.abs(d)
    return p + fol.profile_offset * inward


# ---- constraint arrays for an optimiser ------------------------------------------------------
@dataclass(frozen=True)
class ConstraintArrays:
    """Normalised constraints g ≤ 0 (feasible) at every sample point: the thesis' Eq. 5.2–5.13
    written smoothly (curvature as κ = 1/ρ, which passes through 0 at inflections)."""

    theta: np.ndarray
    g: dict[str, np.ndarray]

    def max_violation(self) -> float:
        return max(float(np.max(v)) for v in self.g.values())


def constraint_arrays(spec: CamSpec, samples: CheckSamples | None = None,
                      model: StateModel | None = None) -> ConstraintArrays:
    """Every constraint as an array over the sample points (default: the spec's sampling)."""
    model = model or StateModel(spec)
    cs = samples or check_samples(model.program, spec.checks.sampling, spec.checks.samples)
    st = model.state(cs.theta, cs.segment)
    cfg = spec.checks
    rr = spec.roller_radius
    moving = np.array([model.program.laws[s] is not None for s in st.segment]) & ~cs.is_end
    seg_scale = np.abs(model.program.lifts[st.segment]) / model.program.spans[st.segment]
    g: dict[str, np.ndarray] = {}
    g["oscillation"] = np.where(moving, -st.travel_velocity / np.where(moving, seg_scale, 1.0), -1.0)  # Eq. 5.2, 5.4
    g["pressure_angle"] = (st.pressure_angle / np.deg2rad(cfg.max_pressure_angle)) ** 2 - 1.0  # Eq. 5.5
    kappa = 1.0 / st.pitch_radius
    if model.follower.design_curve == "profile":
        g["cusp"] = -st.pitch_radius / spec.cam.base_radius                       # a flat face: ρ > 0
    if rr > 0:
        g["curvature"] = kappa * cfg.undercut_factor * rr - 1.0                            # Eq. 5.7
        g["undercut"] = kappa * rr - 1.0
    if cfg.convex:
        g["convexity"] = -kappa * spec.cam.base_radius                                    # Eq. 5.7, signed ρ
    if model.has_load:
        scale = force_reference(spec)
        if not model.form_closed:
            g["separation"] = (cfg.min_force - st.force) / scale                           # Eq. 5.10
        if model.follower.has_contact_stress and spec.material.allowable_stress:
            g["contact_stress"] = (st.stress / spec.material.allowable_stress) ** 2 - 1.0   # Eq. 5.13
    return ConstraintArrays(cs.theta, g)
