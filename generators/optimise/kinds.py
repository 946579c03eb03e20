"""The optimiser's view of each follower kind: its geometric design variables, its design checks
as smooth local functions of (geometry, s, s′, s″) with exact partial derivatives, its closed-curve
integrands (areas, lengths) and the rows that keep its geometry valid.

One class per follower kind, each registered in :data:`KIND_MODELS` for the follower class of
:mod:`cam_workbench.generators.followers` it models:

=============================  ======================  =============================================
follower                       geometry (design vars)  checks (normalised g ≤ 0)
=============================  ======================  =============================================
translating knife / roller     R_b, e                  pressure_angle, curvature, convexity,
                                                       separation, contact_stress (thesis Eq. 3.4–3.7)
oscillating knife / roller     R_b, d, L               the same, for the arm (φ against the velocity
                                                       perpendicular to the arm, ρ of the arc pitch
                                                       curve, F = T/(L cos φ))
translating flat face          R_b, e                  cusp (ρ = R_b + s + s″ > 0), separation,
                                                       contact_stress (flat on convex), face_width
oscillating flat face          R_b, d, f, (L)          pressure_angle (tan φ = −δf/t), cusp
                                                       (ρ = h + h_γγ > 0), turning (the face turns
                                                       slower than the cam), separation (F = T/|t|),
                                                       contact_stress, face_width (pole-free forms:
                                                       :class:`FlatModel`)
=============================  ======================  =============================================

(d = ``pivot_distance``, L = ``arm_length`` — for a flat face the position of its centre —, f =
``face_offset``, t = the contact's position along the face from the foot of the pivot.)

The translating knife/roller keeps the thesis' closed forms with hand-derived partials (Eq.
3.4–3.7; the tests check them by complex step).  The other kinds write their formulas once with
the functions of :mod:`.jet`: on plain arrays they give values (the dense window scans), on
:class:`~.jet.Jet` inputs values and exact partials (the Jacobian at the window maxima).  They are
derived here from the follower geometry of :mod:`cam_workbench.generators.followers` (the fixed-frame point F,
V = F_θ − iδF, W = F_θθ − 2iδF_θ − F; ρ = |V|³/(−δ·V×W)) in real components so that complex
steps pass through them; the tests compare them with the followers' own pressure angle, radius of
curvature and force.

Geometry rows (oscillating kinds), kept ≤ 0 by the solver like the checks, so that every design
the solver ends on builds: x = cos ψ₀ (the arm angle at zero lift; the face angle β₀ for a flat
face) must satisfy −1 < x (the arm reaches the prime circle: R_b > |d − L|; the face touches it:
R_b + f > −d) and x < cos(s_max) (the lift stays below the line through the pivot and the cam axis;
it also gives R_b < d + L).  Outside, the formulas are evaluated at x clamped into (−1, 1): finite
values for the solver, never an exception.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..followers import (Follower, force_reference, OscillatingFlatFollower, OscillatingFollower, TranslatingFlatFollower,
                         TranslatingFollower, follower_of)
from ..errors import SpecError
from ..kinds import body_of
from ..kinds.by_class import ByClass
from ..spec.model import CamSpec
from ..spec.optimise import optimise_variables
from . import jet
from .jet import arccos, arctan, cos, sin, sqrt, where

DEG = math.pi / 180.0
TWO_PI = 2.0 * math.pi
_STRESS_KNEE = 0.9
#: x = cos ψ₀ is clamped into [−1 + X_EPS, 1 − X_EPS] before arccos (outside the valid geometry)
X_EPS = 1e-9

#: spec path of each geometric design variable
GEOMETRY_PATHS = {"base_radius": "cam.base_radius", "offset": "follower.offset",
                  "pivot_distance": "follower.pivot_distance", "arm_length": "follower.arm_length",
                  "face_offset": "follower.face_offset"}


#: follower class → its optimiser model (each model class registers itself below; a new follower
#: kind's model registers itself in a module of its own, imported by ``kinds/builtin.py``)
KIND_MODELS: ByClass[type["KindModel"]] = ByClass("the optimiser's model")


class KindModel:
    """The checks and integrands of one follower kind (see the module docstring).

    ``local(geo, s, v, a, grad)`` → {name: (g, ∂g/∂geo₀, …, ∂g/∂s, ∂g/∂s′, ∂g/∂s″)} (values only,
    a 1-tuple, without ``grad``); ``integrand(which, geo, s, v, a, grad)`` the same for one
    integrand per dθ; ``geometry_rows(geo, grad)`` → (values (r,), partials (r, len(geo)))."""

    #: names of the geometric scalars, in order (the design variables of the kind)
    geometry: tuple[str, ...] = ("base_radius",)
    #: the objective "area": ``thesis_area`` (thesis Eq. 4.21) or ``pitch_area`` (inside the design curve)
    area_integral = "pitch_area"

    def __init__(self, spec: CamSpec, follower: Follower | None = None):
        self.spec = spec
        self.follower = follower or follower_of(spec)
        cfg = spec.checks
        self.sense = 1.0 if spec.cam.direction == "ccw" else -1.0
        self.rr = spec.roller_radius
        self.factor = cfg.undercut_factor
        self.phi_max = math.radians(cfg.max_pressure_angle)
        self.omega = spec.cam.speed_rpm * TWO_PI / 60.0
        ld = self.follower.load
        self.preload = ld.preload
        self.rate = ld.rate
        self.inertia = ld.inertia * ld.mass_force * self.omega**2    # load per unit s″
        self.has_load = ld.any
        self.min_force = cfg.min_force
        self.s_max = spec.max_lift
        mat = spec.material
        delta = ((1 - mat.cam_poisson**2) / mat.modulus("cam", spec.units)
                 + (1 - mat.follower_poisson**2) / mat.modulus("follower", spec.units))
        width = spec.follower.roller_width if spec.is_roller else None
        length = min(spec.cam.thickness, width or spec.cam.thickness)
        self.stress_c = 1.0 / (math.pi * length * delta)
        self.allowable = mat.allowable_stress
        self.length_ref = spec.cam.base_radius     # κ·R_b, ρ/R_b: curvature checks made dimensionless
        self.force_scale = force_reference(spec)
        self.margin = spec.optimise.constraint_margin
        #: a groove cam with body variables: ``local`` also gives the pitch radius and curvature (the
        #: groove's rows of :meth:`SmoothModel.check_rows`)
        self.groove = bool(set(body_of(spec).optimise_variables) & set(optimise_variables(spec)))

    # ---- what the kind checks ---------------------------------------------------------------
    @property
    def families(self) -> list[str]:
        """The constraint families (window-maximised channels) of this kind and spec."""
        raise NotImplementedError


    def start_geometry(self) -> tuple[float, ...]:
        """The spec's values of :attr:`geometry` (optional fields absent: 0)."""
        out = []
        for name in self.geometry:
            path = GEOMETRY_PATHS[name].split(".")
            v = getattr(getattr(self.spec, path[0]), path[1])
            out.append(0.0 if v is None else float(v))
        return tuple(out)

    # ---- the formulas -------------------------------------------------------------------------
    def formulas(self, geo: tuple, s: Any, v: Any, a: Any) -> dict[str, Any]:
        """Every local quantity (plain arrays or jets)."""
        raise NotImplementedError

    def integrands(self, geo: tuple, s: Any, v: Any, a: Any, which: str) -> Any:
        """The integrand ``which`` per dθ (plain arrays or jets)."""
        raise NotImplementedError

    def local(self, geo: tuple, s: np.ndarray, v: np.ndarray, a: np.ndarray, grad: bool = True
              ) -> dict[str, tuple[np.ndarray, ...]]:
        return self._run(lambda g, s_, v_, a_: self.formulas(g, s_, v_, a_), geo, s, v, a, grad)

    def integrand(self, which: str, geo: tuple, s: np.ndarray, v: np.ndarray, a: np.ndarray, grad: bool = True
                  ) -> tuple[np.ndarray, ...]:
        return self._run(lambda g, s_, v_, a_: {"f": self.integrands(g, s_, v_, a_, which)}, geo, s, v, a,
                         grad)["f"]

    def _run(self, fn: Any, geo: tuple, s: np.ndarray, v: np.ndarray, a: np.ndarray, grad: bool
             ) -> dict[str, tuple[np.ndarray, ...]]:
        m = np.shape(s)[0]
        dtype = np.result_type(s, v, a, *[np.asarray(g) for g in geo], float)
        ng = len(geo)
        if not grad:
            out = fn(geo, s, v, a)
            return {k: (np.broadcast_to(jet.value(x), (m,)),) for k, x in out.items()}
        ins = jet.seed([*geo, s, v, a], m, dtype)
        out = fn(tuple(ins[:ng]), ins[ng], ins[ng + 1], ins[ng + 2])
        return {k: jet.unpack(x, m, ng + 3, dtype) for k, x in out.items()}

    def geometry_x(self, geo: tuple) -> Any:
        """cos of the arm (face) angle at zero lift (oscillating kinds), else None."""
        return None

    def geometry_rows(self, geo: tuple, grad: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Rows g ≤ 0 that keep the geometry buildable (see the module docstring)."""
        ng = len(geo)
        if self.geometry_x(tuple(geo)) is None:
            return np.zeros(0), (np.zeros((0, ng)) if grad else None)
        dtype = np.result_type(*[np.asarray(g) for g in geo], float)
        ins = jet.seed(list(geo), 1, dtype) if grad else [np.asarray([g], dtype=dtype) for g in geo]
        x = self.geometry_x(tuple(ins))
        top = math.cos(DEG * self.s_max)
        rows = [x - top, -1.0 - x]
        vals = np.concatenate([np.atleast_1d(jet.value(r)) for r in rows])
        if not grad:
            return vals, None
        return vals, np.vstack([r.d for r in rows])

    def _clamped_x(self, x: Any) -> Any:
        xr = jet.real(x)
        x = where(xr > 1.0 - X_EPS, 1.0 - X_EPS, x)
        return where(jet.real(x) < -1.0 + X_EPS, -1.0 + X_EPS, x)

    # ---- shared pieces -----------------------------------------------------------------------
    def _roller_stress(self, force: Any, kap: Any) -> Any:
        """S²/S_d² − 1 of a roller on the curve of curvature κ − (S² = F/(π t Δ r_f (1 − r_f κ)),
        continued linearly beyond r_f κ = 0.9, far outside the curvature constraint)."""
        rr = self.rr
        xk = rr * kap
        knee = _STRESS_KNEE
        lin = jet.real(xk) > knee
        hh = where(lin, (1 / (1 - knee) + (xk - knee) / (1 - knee) ** 2) / rr, 1 / (rr * (1 - xk)))
        return self.stress_c / self.allowable**2 * force * hh - 1.0

    def _flat_stress(self, force: Any, rho: Any) -> Any:
        """S²/S_d² − 1 of a flat face on the profile of radius ρ (S² = F/(π t Δ ρ); F and ρ may both
        be multiplied by G³); 1/ρ continued by its tangent below ρ_k = margin/2 × R_b (inside the
        cusp constraint's infeasible side)."""
        rk = max(0.5 * self.margin, 1e-9) * self.length_ref
        inv = where(jet.real(rho) > rk, 1.0 / where(jet.real(rho) > rk, rho, rk), 2.0 / rk - rho / (rk * rk))
        return self.stress_c / self.allowable**2 * force * inv - 1.0

    def _pressure(self, phi: Any) -> Any:
        return (phi / self.phi_max) ** 2 - 1.0

    def _separation(self, force: Any) -> Any:
        return (self.min_force - force) / self.force_scale


# ---- translating knife edge and roller (thesis Eq. 3.4–3.7, hand-derived partials) ------------------
@KIND_MODELS.register(TranslatingFollower)
class TranslatingPointModel(KindModel):
    geometry = ("base_radius", "offset")
    area_integral = "thesis_area"

    @property
    def families(self) -> list[str]:
        out = ["pressure_angle"]
        if self.rr > 0:
            out.append("curvature")
        if self.spec.checks.convex:
            out.append("convexity")
        if self.has_load:
            out.append("separation")
            if self.rr > 0 and self.allowable:
                out.append("contact_stress")
        return out

    def local(self, geo, s, v, a, grad=True):
        """Every constraint family and the pressure angle at points with (s, s′, s″), as
        (g, ∂g/∂R, ∂g/∂e, ∂g/∂s, ∂g/∂s′, ∂g/∂s″) — e is the spec's offset (the effective one is
        δe, δ = −1 for a cw cam)."""
        r, e = geo
        sg = self.sense
        s0 = (r * r - e * e) ** 0.5
        y_r, y_e = r / s0, -e / s0                  # ∂Y/∂R, ∂Y/∂e (Y = s₀ + s)
        ee = sg * e
        yy = s0 + s
        w = v - ee
        q = yy * yy + w * w
        sq = q ** 0.5
        phi = np.arctan(w / yy)                     # Y > 0
        ph_y, ph_w = -w / q, yy / q
        out: dict[str, tuple[np.ndarray, ...]] = {}
        zero = 0.0 * s
        families = self.families

        def pack(g_: Any, g_y: Any, g_w: Any, g_v_extra: Any, g_a: Any, g_ee_extra: Any = 0.0, g_s_extra: Any = 0.0):
            # from partials in (Y, w, v|w, a, e_eff|w, s|Y) to (R, e, s, v, a)
            return (g_, g_y * y_r, g_y * y_e + sg * (-g_w + g_ee_extra), g_y + g_s_extra, g_w + g_v_extra, g_a)

        out["phi"] = pack(phi, ph_y, ph_w, zero, zero)
        out["a"] = (a, zero, zero, zero, zero, zero + 1.0)
        gp = 2 * phi / self.phi_max**2
        out["pressure_angle"] = pack((phi / self.phi_max) ** 2 - 1.0, gp * ph_y, gp * ph_w, zero, zero)
        if self.groove:
            rad = (e * e + yy * yy) ** 0.5            # |pitch point| (any sign of e)
            out["pitch_radius"] = pack(rad, yy / rad, zero, zero, zero, sg * e / rad)
        if {"curvature", "convexity", "contact_stress"} & set(families) or self.groove:
            # κ = D/N, D = Y² + w(w + v) − Y s″, N = q^{3/2}  (thesis Eq. 3.7, inverted)
            dd = yy * yy + w * (w + v) - yy * a
            nn = q * sq
            kap = dd / nn
            k_y = ((2 * yy - a) - kap * 3 * yy * sq) / nn
            k_w = ((2 * w + v) - kap * 3 * w * sq) / nn
            k_v = w / nn
            k_a = -yy / nn
            if self.groove:
                out["kappa"] = pack(kap, k_y, k_w, k_v, k_a)
            if "curvature" in families:
                c = self.factor * self.rr
                out["curvature"] = pack(c * kap - 1.0, c * k_y, c * k_w, c * k_v, c * k_a)
            if "convexity" in families:
                c = -self.length_ref
                out["convexity"] = pack(c * kap, c * k_y, c * k_w, c * k_v, c * k_a)
        if self.has_load:
            cph = np.cos(phi)
            qf = self.preload + self.rate * s + self.inertia * a
            force = qf / cph
            f_ph = force * np.tan(phi)
            f_y, f_w = f_ph * ph_y, f_ph * ph_w
            f_a = self.inertia / cph
            f_s = self.rate / cph
            fs = self.force_scale
            out["separation"] = pack((self.min_force - force) / fs, -f_y / fs, -f_w / fs, zero, -f_a / fs,
                                     0.0, -f_s / fs)
            if "contact_stress" in families:
                rr = self.rr
                xk = rr * kap
                knee = _STRESS_KNEE
                lin = xk.real > knee if np.iscomplexobj(xk) else xk > knee
                hh = np.where(lin, (1 / (1 - knee) + (xk - knee) / (1 - knee) ** 2) / rr, 1 / (rr * (1 - xk)))
                h_k = np.where(lin, 1 / (rr * (1 - knee) ** 2), 1 / (rr * (1 - xk) ** 2)) * rr
                cst = self.stress_c / self.allowable**2
                g = cst * force * hh - 1.0
                out["contact_stress"] = pack(g, cst * (f_y * hh + force * h_k * k_y),
                                             cst * (f_w * hh + force * h_k * k_w), cst * force * h_k * k_v,
                                             cst * (f_a * hh + force * h_k * k_a), 0.0, cst * f_s * hh)
        return out

    def integrand(self, which, geo, s, v, a, grad=True):
        """Per dθ: ``thesis_area`` ½(R_b + s)² (thesis Eq. 4.21–4.27), ``pitch_area`` ½(e² + (s₀ + s)²),
        ``pitch_length`` √((s₀ + s)² + (s′ − δe)²), ``thesis_length`` √((R_b + s)² + s′²)."""
        r, e = geo
        sg = self.sense
        zero = 0.0 * s
        if which == "thesis_area":
            rad = r + s
            return (0.5 * rad * rad, rad, zero, rad, zero, zero)
        if which == "thesis_length":
            yy, y_r, y_e, ee = r + s, 1.0, 0.0, 0.0 * e
        else:
            s0 = (r * r - e * e) ** 0.5
            yy, y_r, y_e, ee = s0 + s, r / s0, -e / s0, sg * e
        if which == "pitch_area":
            f = 0.5 * (e * e + yy * yy)
            return (f, yy * y_r, e + yy * y_e, yy, zero, zero)
        if which not in ("pitch_length", "thesis_length"):
            raise ValueError(which)
        ww = v - ee
        root = (yy * yy + ww * ww) ** 0.5
        fy, fw = yy / root, ww / root
        return (root, fy * y_r, fy * y_e - fw * (sg if which != "thesis_length" else 0.0), fy, fw, zero)


# ---- oscillating knife edge and roller ---------------------------------------------------------------
@KIND_MODELS.register(OscillatingFollower)
class OscillatingPointModel(KindModel):
    """A = D + L e^{iψ}, ψ = ψ₀ − s (s in arm degrees), cos ψ₀ = (R_b² − d² − L²)/(2dL)."""

    geometry = ("base_radius", "pivot_distance", "arm_length")

    families = TranslatingPointModel.families

    def geometry_x(self, geo):
        r, d, L = geo[:3]
        return (r * r - d * d - L * L) / (2 * d * L)

    def _curve(self, geo, s, v, a):
        """F, V = F_θ − iδF, W = F_θθ − 2iδF_θ − F (fixed frame, real components), ψ."""
        r, d, L = geo
        dl = self.sense
        psi = arccos(self._clamped_x(self.geometry_x(geo))) - DEG * s
        cp, sp = cos(psi), sin(psi)
        fx, fy = d + L * cp, L * sp
        lv, la = DEG * L * v, DEG * L * a                    # |A_s|·s′, |A_s|·s″
        f1x, f1y = lv * sp, -lv * cp                         # A_s s′ = −iL e^{iψ}·(DEG s′)
        lvv = DEG * lv * v
        f2x, f2y = -lvv * cp + la * sp, -lvv * sp - la * cp  # A_ss s′² + A_s s″
        vx, vy = f1x + dl * fy, f1y - dl * fx
        wx, wy = f2x + 2 * dl * f1y - fx, f2y - 2 * dl * f1x - fy
        return (fx, fy), (vx, vy), (wx, wy), (cp, sp)

    def formulas(self, geo, s, v, a):
        r, d, L = geo
        dl = self.sense
        (fx, fy), (vx, vy), (wx, wy), (cp, sp) = self._curve(geo, s, v, a)
        # tan φ = V·w / (δ V·(−iw)), w = −i e^{iψ} (perpendicular to the arm)
        tan_phi = (DEG * L * v + dl * (L + d * cp)) / (d * sp)
        phi = arctan(tan_phi)
        out: dict[str, Any] = {"phi": phi, "a": a + 0.0 * s, "pressure_angle": self._pressure(phi)}
        fam = self.families
        if self.groove:
            out["pitch_radius"] = sqrt(fx * fx + fy * fy)
        if {"curvature", "convexity", "contact_stress"} & set(fam) or self.groove:
            q = vx * vx + vy * vy
            kap = -dl * (vx * wy - vy * wx) / (q * sqrt(q))      # 1/ρ, ρ = |V|³/(−δ V×W)
            if self.groove:
                out["kappa"] = kap
            if "curvature" in fam:
                out["curvature"] = self.factor * self.rr * kap - 1.0
            if "convexity" in fam:
                out["convexity"] = -self.length_ref * kap
        if self.has_load:
            torque = self.preload + self.rate * DEG * s + self.inertia * DEG * a
            force = torque * sqrt(1.0 + tan_phi * tan_phi) / L    # T/(L cos φ)
            out["separation"] = self._separation(force)
            if "contact_stress" in fam:
                out["contact_stress"] = self._roller_stress(force, kap)
        return out

    def integrands(self, geo, s, v, a, which):
        (fx, fy), (vx, vy), _w, _e = self._curve(geo, s, v, a)
        if which == "pitch_area":
            return -0.5 * self.sense * (fx * vy - fy * vx)     # ½|F × V| (the curve runs cw for ccw)
        if which == "pitch_length":
            return sqrt(vx * vx + vy * vy)
        raise ValueError(f"{which} is not defined for an oscillating follower")


# ---- flat faces ----------------------------------------------------------------------------------------
class FlatModel(KindModel):
    """A flat face (design curve = profile): the support function h(γ) of the face lines.

    The face's normal turns relative to the cam at γ_θ = −δG, G = 1 + δ·s′ (s′ in rad/rad; G = 1
    for a translating face).  ρ = h + h_γγ and the contact's position t = h_γ + … both have a pole
    where G → 0 (the face turning with the cam: the contact runs off to infinity), which a steep
    B-spline lift can reach; so the rows are written pole-free, multiplied by G > 0:

        cusp        −ρG³/R_b,  ρG³ = hG³ − δ(h_θθ γ_θ − h_θ γ_θθ)
        turning     −G                                  (oscillating face: G > 0, the face turns
                                                         slower than the cam)
        face width  ±(tG − (c ± w/2)G)/(w/2)             (centre c given)
        stress      S²/S_d² − 1 = F G³/(ρG³) /(π t Δ S_d²) − 1
        φ           tan φ = −δfG/(tG)

    — equivalent to the dense checks (ρ > 0, |t − c| ≤ w/2) wherever G > 0."""

    def _centre(self) -> float | None:
        return self.follower.face_centre

    @property
    def families(self) -> list[str]:
        osc = self.follower.pivoted
        out = ["pressure_angle", "cusp", "turning"] if osc else ["cusp"]
        if self.has_load:
            out.append("separation")
            if self.allowable:
                out.append("contact_stress")
        if self.spec.follower.face_width is not None:
            out += ["face_span_hi", "face_span_lo"] if self._centre() is None else ["face_hi", "face_lo"]
        return out


    def _terms(self, geo, s, v, a) -> dict[str, Any]:
        """h, G, ρG³, tG, φ (None: 0) and the contact force F of the kind."""
        raise NotImplementedError

    def formulas(self, geo, s, v, a):
        q = self._terms(geo, s, v, a)
        big_g, rho3, tg, phi = q["G"], q["rhoG3"], q["tG"], q["phi"]
        out: dict[str, Any] = {"a": a + 0.0 * s, "cusp": -rho3 / self.length_ref}
        out["phi"] = phi if phi is not None else 0.0 * s
        if phi is not None:
            out["pressure_angle"] = self._pressure(phi)
            out["turning"] = -big_g
        if self.has_load:
            force = q["force"]
            out["separation"] = self._separation(force)
            if self.allowable:
                out["contact_stress"] = self._flat_stress(force * big_g**3, rho3)
        w = self.spec.follower.face_width
        if w is not None:
            centre = self._face_centre(geo)
            if centre is None:
                out["face_span_hi"] = tg / (big_g * w)
                out["face_span_lo"] = -tg / (big_g * w)
            else:
                out["face_hi"] = (tg - (centre + 0.5 * w) * big_g) / (0.5 * w)
                out["face_lo"] = (-tg + (centre - 0.5 * w) * big_g) / (0.5 * w)
        return out

    def _face_centre(self, geo) -> Any:
        return self._centre()

    def integrands(self, geo, s, v, a, which):
        q = self._terms(geo, s, v, a)
        # |V| = |ρ γ_θ| = |ρG³|/G², F × V = −δ ρ G h: ½|∮ F × V dθ| = ½∮ ρ h G dθ (the support-function
        # area ½∮ h(h + h_γγ) dγ)
        rho_g = q["rhoG3"] / q["G"] ** 2
        if which == "pitch_area":
            return 0.5 * rho_g * q["h"]
        if which == "pitch_length":
            return sqrt(rho_g * rho_g)
        if which == "thesis_length" and not self.follower.pivoted:
            r = geo[0]
            return sqrt((r + s) ** 2 + v * v)
        raise ValueError(f"{which} is not defined for a flat face")


@KIND_MODELS.register(TranslatingFlatFollower)
class TranslatingFlatModel(FlatModel):
    """The face y = R_b + s: ρ = R_b + s + s″, contact at x = δs′, F = P_L + k s + M s″ω²."""

    geometry = ("base_radius", "offset")

    def _terms(self, geo, s, v, a):
        r, e = geo
        dl = self.sense
        h = r + s
        force = self.preload + self.rate * s + self.inertia * a
        return {"h": h, "G": 1.0 + 0.0 * s, "rhoG3": h + a, "tG": dl * v - e, "phi": None, "force": force}


@KIND_MODELS.register(OscillatingFlatFollower)
class OscillatingFlatModel(FlatModel):
    """The face at f from the pivot, normal e^{iβ}, β = β₀ − s, cos β₀ = (R_b + f)/d:
    h = d cos β − f, ρ = h + h_γγ, t = h_γ + d sin β, tan φ = −δf/t, F = T/|t|."""

    geometry = ("base_radius", "pivot_distance", "face_offset", "arm_length")

    def geometry_x(self, geo):
        r, d, f = geo[:3]
        return (r + f) / d

    def _face_centre(self, geo):
        return None if self._centre() is None else geo[3]

    def _terms(self, geo, s, v, a):
        r, d, f = geo[:3]
        dl = self.sense
        beta = arccos(self._clamped_x(self.geometry_x(geo))) - DEG * s
        cb, sb = cos(beta), sin(beta)
        vi, ai = DEG * v, DEG * a
        g1 = -vi - dl                            # γ_θ (β_s = −1 per rad) = −δG
        g2 = -ai
        big_g = 1.0 + dl * vi
        h = d * cb - f
        h1 = d * sb * vi                         # h_θ
        h2 = -d * cb * vi * vi + d * sb * ai     # h_θθ
        rho3 = h * big_g**3 - dl * (h2 * g1 - h1 * g2)      # ρG³ (ρ = h + (h₂γ_θ − h₁γ_θθ)/γ_θ³)
        tg = -dl * h1 + d * sb * big_g                      # tG, t = h_θ/γ_θ + d sin β
        # tan φ = −δf/t = −δfG/(tG); where |tG| < |f|G: φ = ±π/2 + atan(δ tG/(fG)) (no pole)
        tr, fr, gr = jet.real(tg), np.real(jet.value(f)), jet.real(big_g)
        far = np.abs(tr) >= np.abs(fr) * np.abs(gr)
        safe_t = where(far, tg, 1.0)
        safe_f = where(far, 1.0, f * big_g)
        phi = where(far, arctan(-dl * f * big_g / safe_t),
                    np.sign(-dl * fr * tr * gr) * (np.pi / 2) + arctan(dl * tg / safe_f))
        torque = self.preload + self.rate * DEG * s + self.inertia * DEG * a
        lever = tg * np.sign(np.where(tr == 0, 1.0, tr))                 # |t|·G: the lever about the pivot × G
        return {"h": h, "G": big_g, "rhoG3": rho3, "tG": tg, "phi": phi, "force": torque * big_g / lever}


def kind_model(spec: CamSpec) -> KindModel:
    """The optimiser model of the spec's follower kind.

    Raises:
        SpecError: no model is registered for the follower's class (naming ``follower.kind``).
    """
    fol = follower_of(spec)
    model = KIND_MODELS.for_class(type(fol))
    if model is None:
        raise SpecError("follower.kind", f"the optimiser has no model of the {spec.follower.motion} "
                                         f"{spec.follower.kind} follower (docs/adding-a-kind.md)")
    return model(spec, fol)


__all__ = ["GEOMETRY_PATHS", "KIND_MODELS", "KindModel", "force_reference", "kind_model"]
