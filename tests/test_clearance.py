"""Clearances between moving tools (generators/machine/clearance.py) against closed forms and
independent computations written here: two circles on straight or harmonic paths (closed-form
minimum and its machine angle), brute-force dense sampling of both outlines' boundaries, and, for
convex overlaps, a dense scan of all projection directions (the penetration depth of two convex
sets is the smallest projection overlap over every direction; their distance the largest gap)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine.clearance import (Circle, Clearance, Polygon, Poses, clearance_check,
                                                        min_clearance, phase_sweep, shortest_cycle,
                                                        signed_distance)


# ---- independent helpers ----------------------------------------------------------------------
def world_boundary(outline, position, angle, s):
    """Boundary points of ``outline`` at one pose, at parameters ``s`` (circle: angle [rad];
    polygon: edge index + fraction)."""
    c, sn = math.cos(angle), math.sin(angle)
    if isinstance(outline, Circle):
        local = np.c_[outline.centre[0] + outline.radius * np.cos(s), outline.centre[1] + outline.radius * np.sin(s)]
    else:
        v = np.asarray(outline.vertices)
        n = len(v)
        s = np.mod(s, n)
        i = np.floor(s).astype(int) % n
        f = (s - np.floor(s))[:, None]
        local = v[i] * (1 - f) + v[(i + 1) % n] * f
    return np.c_[c * local[:, 0] - sn * local[:, 1] + position[0], sn * local[:, 0] + c * local[:, 1] + position[1]]


def period(outline):
    return 2 * math.pi if isinstance(outline, Circle) else float(len(outline.vertices))


def brute_distance(oa, pos_a, ang_a, ob, pos_b, ang_b, n=20000, zooms=3, keep=8):
    """Distance between two boundaries by dense sampling of both (KD-tree nearest pairs), then
    re-sampling around the best pairs ``zooms`` times with a 1000× finer step each time."""
    sa = np.linspace(0, period(oa), n, endpoint=False)
    sb = np.linspace(0, period(ob), n, endpoint=False)
    ha, hb = sa[1], sb[1]
    best = math.inf
    for _ in range(zooms + 1):
        pa = world_boundary(oa, pos_a, ang_a, sa)
        pb = world_boundary(ob, pos_b, ang_b, sb)
        d, j = cKDTree(pb).query(pa)
        best = min(best, float(d.min()))
        order = np.argsort(d)[:keep]
        centres_a, centres_b = sa[order], sb[j[order]]
        ha, hb = ha / 1000 * 2, hb / 1000 * 2
        sa = (centres_a[:, None] + np.linspace(-500, 500, 1001)[None, :] * ha).ravel()
        sb = (centres_b[:, None] + np.linspace(-500, 500, 1001)[None, :] * hb).ravel()
    return best


def support(outline, position, angle, u):
    """max over the outline of u·x, for unit directions u (K, 2)."""
    c, sn = math.cos(angle), math.sin(angle)
    if isinstance(outline, Circle):
        ctr = np.array([c * outline.centre[0] - sn * outline.centre[1] + position[0],
                        sn * outline.centre[0] + c * outline.centre[1] + position[1]])
        return u @ ctr + outline.radius
    v = np.asarray(outline.vertices)
    w = np.c_[c * v[:, 0] - sn * v[:, 1] + position[0], sn * v[:, 0] + c * v[:, 1] + position[1]]
    return (u @ w.T).max(axis=1)


def direction_scan(oa, pos_a, ang_a, ob, pos_b, ang_b, n=200000, zooms=2):
    """Signed distance of two CONVEX outlines: max over all directions u of the gap
    min_B u·b − max_A u·a (= distance when apart, −penetration depth when overlapping)."""
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    step = th[1]
    best = -math.inf
    for _ in range(zooms + 1):
        u = np.c_[np.cos(th), np.sin(th)]
        gap = -support(ob, pos_b, ang_b, -u) - support(oa, pos_a, ang_a, u)
        k = int(np.argmax(gap))
        best = max(best, float(gap[k]))
        th = th[k] + np.linspace(-2, 2, 4001) * step
        step = th[1] - th[0]
    return best


def circle_dist(ca, ra, cb, rb):
    return np.hypot(cb[..., 0] - ca[..., 0], cb[..., 1] - ca[..., 1]) - ra - rb


# ---- circles in closed form -------------------------------------------------------------------
def crossing_lines(u=0.5, w=0.3, X=30.0, Y=25.0):
    """A on the x axis at (u θ − X, 0), B on the y axis at (0, w θ − Y) [mm, θ in deg]: B − A =
    (X − u θ, w θ − Y), nearest at θ* = (uX + wY)/(u² + w²), |Xw − Yu|/√(u² + w²) apart."""
    def ma(x):
        x = np.asarray(x, float)
        return np.c_[u * x - X, 0 * x]

    def mb(x):
        x = np.asarray(x, float)
        return np.c_[0 * x, w * x - Y]

    theta = (u * X + w * Y) / (u * u + w * w)
    gap = abs(X * w - Y * u) / math.hypot(u, w)
    return ma, mb, theta, gap


@pytest.mark.parametrize("ra, rb", [(1.0, 2.0), (4.0, 3.0)])
def test_circles_on_crossing_lines_refined_closed_form(ra, rb):
    ma, mb, theta, gap = crossing_lines()
    t = np.linspace(0.0, 120.0, 13)                          # 10° samples: θ* = 66.18° lies between
    c = min_clearance(Circle(ra), ma(t), Circle(rb), mb(t), t, motion_a=ma, motion_b=mb)
    assert c.refined
    assert c.distance == pytest.approx(gap - ra - rb, abs=1e-9)
    assert c.angle_deg == pytest.approx(theta, abs=1e-4)
    assert c.overlap == (gap < ra + rb)
    assert c.error_bound <= 1e-6
    # the closest points lie on the circles, along the centre line, B's direction from A
    ca, cb = ma([c.angle_deg])[0], mb([c.angle_deg])[0]
    assert np.hypot(*(c.point_a - ca)) == pytest.approx(ra, abs=1e-9)
    assert np.hypot(*(c.point_b - cb)) == pytest.approx(rb, abs=1e-9)
    assert np.allclose(c.direction, (cb - ca) / np.hypot(*(cb - ca)), atol=1e-9)


def test_overlapping_circles_give_closed_form_penetration():
    ma, mb, theta, gap = crossing_lines()
    ra, rb = 4.0, 3.0                                        # gap 6.0025 < 7: about 1 mm deep at θ*
    t = np.linspace(0.0, 120.0, 13)
    c = min_clearance(Circle(ra), ma(t), Circle(rb), mb(t), t, motion_a=ma, motion_b=mb)
    assert c.distance == pytest.approx(-(ra + rb - gap), abs=1e-9) and c.distance < 0
    assert c.overlap and c.exact_depth
    # the witnesses are one depth apart, and moving B by the depth along `direction` makes them touch
    assert np.hypot(*(c.point_a - c.point_b)) == pytest.approx(-c.distance, abs=1e-9)
    cb = mb([c.angle_deg])[0] + (-c.distance) * c.direction
    assert circle_dist(ma([c.angle_deg])[0], ra, cb, rb) == pytest.approx(0.0, abs=1e-9)


def test_sampled_result_and_its_error_bound_circles_on_crossing_lines():
    ma, mb, theta, gap = crossing_lines()
    true = gap - 3.0
    for n in (13, 49, 193):
        t = np.linspace(0.0, 120.0, n)
        c = min_clearance(Circle(1.0), ma(t), Circle(2.0), mb(t), t)
        assert not c.refined
        assert c.distance >= true - 1e-12                    # a sampled value never lies below the true minimum
        assert c.distance - c.error_bound <= true + 1e-12    # and the bound covers the dip between samples
        # the relative speed is √(u² + w²) mm/°: the bound is at most half a step's travel
        assert c.error_bound <= 0.5 * math.hypot(0.5, 0.3) * (120.0 / (n - 1)) + 1e-12


def test_harmonic_path_against_fixed_circle_closed_form():
    """A on x = R cos θ, y = 0; B fixed at (D, 0): distance D − R cos θ − ra − rb, least at θ = 0
    (and 360): sampled there exactly."""
    R, D, ra, rb = 10.0, 25.0, 1.5, 2.5
    t = np.linspace(0.0, 360.0, 73)
    a = np.c_[R * np.cos(np.radians(t)), 0 * t]
    b = np.c_[D + 0 * t, 0 * t]
    c = min_clearance(Circle(ra), a, Circle(rb), b, t)
    assert c.distance == pytest.approx(D - R - ra - rb, abs=1e-12)
    assert c.angle_deg in (0.0, 360.0)
    assert np.allclose(signed_distance(Circle(ra), a, Circle(rb), b),
                       D - R * np.cos(np.radians(t)) - ra - rb, atol=1e-12)


def test_off_centre_circle_on_a_rotating_arm_closed_form():
    """A circle of radius r at (L, 0) on an arm turning about the origin by θ; B fixed at (0, H):
    the centres are √(L² + H² − 2LH sin θ) apart, nearest at θ = 90°."""
    L, H, r, rb = 8.0, 14.0, 1.0, 2.0
    t = np.linspace(0.0, 180.0, 7)                           # 30° samples: 90° is a sample
    ang = np.radians(t)

    def ma(x):
        return Poses(np.zeros((len(x), 2)), np.radians(x))

    def mb(x):
        return Poses(np.c_[0 * np.asarray(x), H + 0 * np.asarray(x)])

    c = min_clearance(Circle(r, (L, 0.0)), Poses(np.zeros((len(t), 2)), ang), Circle(rb), mb(t), t,
                      motion_a=ma, motion_b=mb)
    assert c.distance == pytest.approx(H - L - r - rb, abs=1e-9)
    assert c.angle_deg == pytest.approx(90.0, abs=1e-3)


# ---- brute force: circle–polygon and polygon–polygon ------------------------------------------
L_SHAPE = Polygon([[0, 0], [6, 0], [6, 2], [2, 2], [2, 6], [0, 6]])        # not convex
HEX = Polygon([[np.cos(a) * 2.0, np.sin(a) * 1.4] for a in np.linspace(0, 2 * np.pi, 6, endpoint=False)])
TRI = Polygon([[0, 0], [3, 0.5], [1, 2.5]])


@pytest.mark.parametrize("ob", [HEX, TRI, L_SHAPE])
def test_circle_polygon_against_dense_sampling(ob):
    rng = np.random.default_rng(7)
    oa = Circle(0.8, (0.3, -0.2))
    n = 0
    while n < 6:
        pos_a, pos_b = rng.uniform(-6, 6, 2), rng.uniform(-2, 2, 2)
        ang_a, ang_b = rng.uniform(-np.pi, np.pi, 2)
        d = float(signed_distance(oa, Poses(pos_a[None], [ang_a]), ob, Poses(pos_b[None], [ang_b]))[0])
        if d < 0.05:
            continue
        n += 1
        ref = brute_distance(oa, pos_a, ang_a, ob, pos_b, ang_b)
        assert d == pytest.approx(ref, abs=1e-6)
        # swapping the tools gives the same distance
        d2 = float(signed_distance(ob, Poses(pos_b[None], [ang_b]), oa, Poses(pos_a[None], [ang_a]))[0])
        assert d2 == pytest.approx(d, abs=1e-12)


@pytest.mark.parametrize("oa, ob", [(HEX, TRI), (L_SHAPE, TRI), (L_SHAPE, HEX), (L_SHAPE, L_SHAPE)])
def test_polygon_polygon_against_dense_sampling(oa, ob):
    rng = np.random.default_rng(11)
    n = 0
    while n < 6:
        pos_a, pos_b = rng.uniform(-1, 1, 2), rng.uniform(-9, 9, 2)
        ang_a, ang_b = rng.uniform(-np.pi, np.pi, 2)
        d = float(signed_distance(oa, Poses(pos_a[None], [ang_a]), ob, Poses(pos_b[None], [ang_b]))[0])
        if d < 0.05:
            continue
        n += 1
        assert d == pytest.approx(brute_distance(oa, pos_a, ang_a, ob, pos_b, ang_b), abs=1e-6)


def test_triangle_in_the_notch_of_an_l_shape():
    """A triangle poking into the L's notch (convex hulls overlap, the outlines do not): the
    distance is the one brute force finds, positive."""
    pos_b = np.array([3.2, 3.1])
    d = float(signed_distance(L_SHAPE, Poses([[0.0, 0.0]]), TRI, Poses(pos_b[None], [0.1]))[0])
    assert d > 0
    assert d == pytest.approx(brute_distance(L_SHAPE, (0, 0), 0.0, TRI, pos_b, 0.1), abs=1e-6)


@pytest.mark.parametrize("oa, ob", [(HEX, TRI), (Circle(1.1), HEX), (TRI, Circle(0.7)), (HEX, HEX)])
def test_convex_overlap_depth_against_direction_scan(oa, ob):
    rng = np.random.default_rng(3)
    n = 0
    while n < 6:
        pos_a, pos_b = rng.uniform(-1, 1, 2), rng.uniform(-1.5, 1.5, 2)
        ang_a, ang_b = rng.uniform(-np.pi, np.pi, 2)
        d = float(signed_distance(oa, Poses(pos_a[None], [ang_a]), ob, Poses(pos_b[None], [ang_b]))[0])
        if d > -0.02:
            continue
        n += 1
        assert d == pytest.approx(direction_scan(oa, pos_a, ang_a, ob, pos_b, ang_b), abs=1e-6)


def test_convex_overlap_witnesses_and_direction_separate_the_tools():
    """Moving B by the depth along `direction` leaves the convex tools touching (distance 0)."""
    t = np.array([0.0, 1.0])
    a = Poses([[0.0, 0.0], [0.0, 0.0]], [0.2, 0.2])
    b = Poses([[1.5, 0.4], [1.5, 0.4]], [-0.4, -0.4])
    c = min_clearance(HEX, a, TRI, b, t)
    assert c.overlap and c.exact_depth and c.distance < 0
    moved = Poses([[1.5, 0.4] + (-c.distance) * c.direction], [-0.4])
    assert float(signed_distance(HEX, Poses([[0.0, 0.0]], [0.2]), TRI, moved)[0]) == pytest.approx(0, abs=1e-9)
    assert np.hypot(*(c.point_a - c.point_b)) == pytest.approx(-c.distance, abs=1e-9)


def test_non_convex_overlap_is_negative_and_flagged_a_lower_bound():
    # a thin bar across the L's arm: edges cross, no vertex inside the other → depth lower bound 0
    bar = Polygon([[-1, 0.9], [8, 0.9], [8, 1.1], [-1, 1.1]])
    c = min_clearance(L_SHAPE, Poses([[0.0, 0.0]] * 2), bar, Poses([[0.0, 0.0]] * 2), [0.0, 1.0])
    assert c.overlap and not c.exact_depth and c.distance <= 0
    # the bar's corner 1 mm deep inside the L's foot (nearest boundary 0.5 mm away): at least 0.5 mm deep
    box = Polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    c = min_clearance(L_SHAPE, Poses([[0.0, 0.0]] * 2), box, Poses([[4.0, 1.5]] * 2), [0.0, 1.0])
    assert c.overlap and not c.exact_depth
    assert c.distance == pytest.approx(-0.5, abs=1e-12)


def test_polygon_sweeping_past_a_circle_refined_against_brute_force():
    """A hexagon turning and sliding past a fixed circle: the refined minimum over the cycle
    against the brute-force distance minimised over a fine machine-angle grid."""
    def ma(x):
        x = np.radians(np.asarray(x, float))
        return Poses(np.c_[6 * np.cos(x), 2 * np.sin(x)], 0.7 * x)

    def mb(x):
        return Poses(np.tile([9.5, 1.0], (len(np.asarray(x)), 1)))

    t = np.linspace(0, 360, 25)
    c = min_clearance(HEX, ma(t), Circle(0.5), mb(t), t, motion_a=ma, motion_b=mb)
    fine = np.linspace(c.angle_deg - 2, c.angle_deg + 2, 4001)
    brute = min(brute_distance(HEX, ma([x]).positions[0], ma([x]).angles[0], Circle(0.5), (9.5, 1.0), 0.0,
                               n=4000, zooms=1)
                for x in fine[::200])
    assert c.distance <= brute + 1e-6
    # a continuous minimum: the code's own per-sample distances on the fine grid never go below it
    d = signed_distance(HEX, ma(fine), Circle(0.5), mb(fine))
    assert d.min() >= c.distance - 1e-9
    assert c.distance == pytest.approx(brute_distance(HEX, ma([c.angle_deg]).positions[0],
                                                      ma([c.angle_deg]).angles[0], Circle(0.5), (9.5, 1.0),
                                                      0.0), abs=1e-6)


# ---- hypothesis: symmetry and invariance ------------------------------------------------------
def convex_polygon(draw):
    n = draw(st.integers(3, 8))
    angles = sorted(draw(st.lists(st.floats(0, 2 * np.pi - 1e-3), min_size=n, max_size=n, unique=True)))
    gaps = np.diff(np.r_[angles, angles[0] + 2 * np.pi])
    if gaps.min() < 0.05 or gaps.max() > np.pi - 0.05:
        angles = np.linspace(0, 2 * np.pi, n, endpoint=False) + angles[0]
    ax, ay = draw(st.floats(0.5, 3)), draw(st.floats(0.5, 3))
    return Polygon(np.c_[ax * np.cos(angles), ay * np.sin(angles)] + [draw(st.floats(-1, 1)), draw(st.floats(-1, 1))])


@st.composite
def outlines(draw):
    if draw(st.booleans()):
        return convex_polygon(draw)
    return Circle(draw(st.floats(0.2, 2.5)), (draw(st.floats(-1, 1)), draw(st.floats(-1, 1))))


poses = st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-np.pi, np.pi))


@settings(max_examples=150, deadline=None)
@given(oa=outlines(), ob=outlines(), a=poses, b=poses, motion=poses, pivot=st.tuples(st.floats(-5, 5), st.floats(-5, 5)))
def test_hypothesis_convex_signed_distance(oa, ob, a, b, motion, pivot):
    pa, pb = Poses([a[:2]], [a[2]]), Poses([b[:2]], [b[2]])
    d = float(signed_distance(oa, pa, ob, pb)[0])
    # symmetric: swapping A and B
    assert float(signed_distance(ob, pb, oa, pa)[0]) == pytest.approx(d, abs=1e-9)
    # invariant to a common rigid motion: rotate both about `pivot` by α, then translate
    al, c, s = motion[2], math.cos(motion[2]), math.sin(motion[2])

    def moved(p):
        x, y = p[0] - pivot[0], p[1] - pivot[1]
        return [c * x - s * y + pivot[0] + motion[0], s * x + c * y + pivot[1] + motion[1]]

    d2 = float(signed_distance(oa, Poses([moved(a)], [a[2] + al]), ob, Poses([moved(b)], [b[2] + al]))[0])
    assert d2 == pytest.approx(d, abs=1e-9)
    # and equal to the independent direction scan (convex outlines: gap or −depth)
    assert d == pytest.approx(direction_scan(oa, a[:2], a[2], ob, b[:2], b[2], n=20000), abs=1e-6)


@settings(max_examples=40, deadline=None)
@given(oa=outlines(), ob=outlines(), seed=st.integers(0, 2**32 - 1))
def test_hypothesis_min_clearance_swap(oa, ob, seed):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 360, 37)
    pa = Poses(rng.uniform(-4, 4, (37, 2)), rng.uniform(-3, 3, 37))
    pb = Poses(rng.uniform(-4, 4, (37, 2)), rng.uniform(-3, 3, 37))
    c1 = min_clearance(oa, pa, ob, pb, t)
    c2 = min_clearance(ob, pb, oa, pa, t)
    assert c1.distance == pytest.approx(c2.distance, abs=1e-9)
    assert c1.error_bound == pytest.approx(c2.error_bound, rel=1e-12, abs=1e-12)
    if abs(c1.distance - np.sort(signed_distance(oa, pa, ob, pb))[1]) > 1e-9:   # a unique minimum
        assert c1.angle_deg == c2.angle_deg
        assert np.allclose(c1.point_a, c2.point_b, atol=1e-9) or c1.overlap


# ---- the check --------------------------------------------------------------------------------
def test_clearance_check_pass_fail_and_remedy():
    ma, mb, theta, gap = crossing_lines()                    # 6.0025 mm between the centres at θ*
    t = np.linspace(0.0, 120.0, 13)
    near = min_clearance(Circle(1.0), ma(t), Circle(2.0), mb(t), t, motion_a=ma, motion_b=mb)   # gap − 3
    deep = min_clearance(Circle(4.0), ma(t), Circle(3.0), mb(t), t, motion_a=ma, motion_b=mb)   # gap − 7 < 0
    res = clearance_check({"slide–gripper": near, "pusher–gripper": deep}, {"slide–gripper": 2.5,
                                                                           "pusher–gripper": 0.5})
    assert [r.status for r in res] == ["pass", "fail"]
    fail = res[1]
    assert fail.remedy["at_deg"] == pytest.approx(theta, abs=1e-4)
    assert fail.remedy["shift"] == pytest.approx(0.5 - (gap - 7.0), abs=2e-6)
    # B moved by the shift along the direction at that angle clears by the required 0.5 mm there
    x = fail.remedy["at_deg"]
    cb = mb([x])[0] + fail.remedy["shift"] * np.array(fail.remedy["direction"])
    assert circle_dist(ma([x])[0], 4.0, cb, 3.0) >= 0.5 - 1e-9
    assert fail.to_dict()["remedy"]["unit"] == "mm"
    res = clearance_check({"slide–gripper": near}, 3.5)
    assert res[0].status == "fail" and res[0].remedy["shift"] == pytest.approx(3.5 - (gap - 3.0), abs=2e-6)


def test_clearance_check_sampled_near_the_limit_notes_the_error():
    ma, mb, theta, gap = crossing_lines()
    t = np.linspace(0.0, 120.0, 13)
    c = min_clearance(Circle(1.0), ma(t), Circle(2.0), mb(t), t)
    (r,) = clearance_check({"p": c}, c.distance - 0.5 * c.error_bound)
    assert r.status == "pass" and "sampling error" in r.note
    (r,) = clearance_check({"p": c}, c.distance + 0.1)
    assert r.remedy["shift"] == pytest.approx(0.1 + c.error_bound, abs=1e-12)


# ---- phase sweep --------------------------------------------------------------------------------
def opposed_harmonics(a=5.0, D=16.0, ra=1.0, rb=1.5):
    """A on x = a cos ψ, B on x = D − a cos(ψ − φ) (both y = 0): the gap D − ra − rb −
    2a cos(ψ − φ/2) cos(φ/2) is least over ψ at D − ra − rb − 2a|cos(φ/2)|."""
    def ma(x):
        return np.c_[a * np.cos(np.radians(x)), 0 * np.asarray(x)]

    def mb(x):
        return np.c_[D - a * np.cos(np.radians(x)), 0 * np.asarray(x)]

    def c_of(phi):
        return D - ra - rb - 2 * a * np.abs(np.cos(np.radians(phi) / 2))

    return Circle(ra), ma, Circle(rb), mb, c_of


def test_phase_sweep_boundaries_closed_form():
    oa, ma, ob, mb, c_of = opposed_harmonics()
    req = 8.0
    k = (16.0 - 2.5 - req) / 10.0                            # |cos(φ/2)| ≤ k keeps the clearance
    lo = math.degrees(2 * math.acos(k))
    sw = phase_sweep(oa, ma, ob, mb, req, phases=90, samples=3600)
    assert np.allclose(sw.clearance, c_of(sw.phases), atol=sw.error_bound + 1e-12)
    assert np.all(sw.clearance >= c_of(sw.phases) - 1e-12)
    assert len(sw.intervals) == 1
    start, end = sw.intervals[0]
    # the boundary is exact up to the sampling error of c(φ): |Δφ| ≤ error / |dc/dφ|
    slope = 10.0 * math.sin(math.radians(lo) / 2) * 0.5 * math.pi / 180
    assert start == pytest.approx(lo, abs=sw.error_bound / slope + 1e-9)
    assert end == pytest.approx(360 - lo, abs=sw.error_bound / slope + 1e-9)
    assert sw.error_bound < 1e-3
    assert sw.feasible(180.0) and not sw.feasible(0.0) and not sw.feasible(lo - 1)


def test_phase_sweep_against_brute_force_scan_with_rotating_polygon():
    """A rotating triangle against a circle on a sinusoid: the feasible phases against a brute
    scan (phases × machine angles, circle-to-edge distances written here)."""
    tri = Polygon([[-1.0, -0.6], [1.4, 0.0], [-1.0, 0.6]])

    def ma(x):
        x = np.radians(np.asarray(x, float))
        return Poses(np.c_[np.cos(x), 0 * x], 0.4 * np.sin(x))

    def mb(x):
        x = np.radians(np.asarray(x, float))
        return np.c_[3.5 + np.cos(x), 0.3 * np.sin(x)]

    req = 0.5
    sw = phase_sweep(tri, ma, Circle(0.4), mb, req, phases=72, samples=1440)
    phi = np.linspace(0, 360, 361)[:-1]
    psi = np.linspace(0, 360, 1441)
    # brute: the circle centre to the rotated triangle's edges, densely sampled along each edge
    ang = 0.4 * np.sin(np.radians(psi))
    v = np.asarray(tri.vertices)
    f = np.linspace(0, 1, 201)
    edges = (v[:, None, :] * (1 - f)[None, :, None] + np.roll(v, -1, 0)[:, None, :] * f[None, :, None]).reshape(-1, 2)
    c, s = np.cos(ang), np.sin(ang)
    wx = c[:, None] * edges[None, :, 0] - s[:, None] * edges[None, :, 1] + np.cos(np.radians(psi))[:, None]
    wy = s[:, None] * edges[None, :, 0] + c[:, None] * edges[None, :, 1]
    feasible = np.empty(len(phi), bool)
    for i, p in enumerate(phi):
        cb = mb((psi - p) % 360)
        d = np.sqrt((wx - cb[:, 0:1]) ** 2 + (wy - cb[:, 1:2]) ** 2).min(axis=1) - 0.4
        feasible[i] = d.min() >= req
    mine = np.array([sw.feasible(p) for p in phi])
    disagree = phi[mine != feasible]
    edges_found = [e % 360 for iv in sw.intervals for e in iv]
    # they may only disagree next to a boundary the sweep found (the brute scan samples coarser)
    assert all(min(abs((x - e + 180) % 360 - 180) for e in edges_found) <= 1.0 for x in disagree)
    assert 0 < feasible.sum() < len(phi)


def test_shortest_cycle_overlap_closed_form():
    oa, ma, ob, mb, c_of = opposed_harmonics()
    req = 8.0
    lo = math.degrees(2 * math.acos((16.0 - 2.5 - req) / 10.0))
    # sequential: A moves 0…180°, B 0…180° of its own cam: φ0 = 180°, feasible down to `lo`
    sc = shortest_cycle(oa, ma, (0.0, 180.0), ob, mb, (0.0, 180.0), req, phases=90, samples=3600)
    tol = 1e-3
    assert sc.sequential_phase == 180.0
    assert sc.overlap == pytest.approx(180.0 - lo, abs=tol)
    assert sc.phase == pytest.approx(lo, abs=tol)
    assert sc.combined_span == pytest.approx(360.0 - (180.0 - lo), abs=tol)
    assert sc.limited_by == "clearance"
    # φ0 = 0 does not keep the clearance: B must wait until φ = lo (a negative overlap)
    sc = shortest_cycle(oa, ma, (0.0, 90.0), ob, mb, (90.0, 180.0), req, phases=90, samples=3600)
    assert sc.sequential_phase == 0.0
    assert sc.overlap == pytest.approx(-lo, abs=tol)
    # a small requirement: every phase passes; the overlap is A's whole span
    sc = shortest_cycle(oa, ma, (0.0, 120.0), ob, mb, (0.0, 180.0), 1.0, phases=36, samples=360)
    assert sc.overlap == 120.0 and sc.limited_by == "span"
    # nothing passes
    sc = shortest_cycle(oa, ma, (0.0, 120.0), ob, mb, (0.0, 180.0), 20.0, phases=36, samples=360)
    assert sc.phase is None and sc.limited_by == "none"


# ---- bad input --------------------------------------------------------------------------------
@pytest.mark.parametrize("make, field, words", [
    (lambda: Circle(0.0), "radius", "> 0"),
    (lambda: Circle(1.0, (0.0, float("nan"))), "centre", "finite"),
    (lambda: Polygon([[0, 0], [1, 0]]), "vertices", "V >= 3"),
    (lambda: Polygon([[0, 0], [1, 1], [1, 0], [0, 1]]), "vertices", "must be simple"),
    (lambda: Polygon([[0, 0], [1, 0], [2, 0]]), "vertices", "area"),
    (lambda: Polygon([[0, 0], [1, 0], [1, 0], [0, 1]]), "vertices", "length > 0"),
    (lambda: Poses([[0, 0], [1, 1]], [0.0]), "angles", "one per position"),
    (lambda: Poses([[0, 0, 0]]), "positions", "(N, 2)"),
    (lambda: min_clearance(Circle(1), [[0, 0], [1, 0]], Circle(1), [[5, 0]], [0, 1]), "poses_b", "one per machine angle"),
    (lambda: min_clearance(Circle(1), [[0, 0], [1, 0]], Circle(1), [[5, 0], [5, 0]], [1, 1]), "machine_angle",
     "increase strictly"),
    (lambda: min_clearance(Circle(1), [[0, 0], [1, 0]], "disc", [[5, 0], [5, 0]], [0, 1]), "outline_b", "Circle or a Polygon"),
    (lambda: min_clearance(Circle(1), [[0, 0], [1, 0]], Circle(1), [[5, 0], [5, 0]], [0, 1],
                           motion_a=lambda x: np.zeros((len(x), 2))), "motion_b", "both pose functions"),
    (lambda: clearance_check({"p": 1.0}, 1.0), "pairs.p", "Clearance"),
    (lambda: clearance_check({}, -1.0), "required", ">= 0"),
    (lambda: phase_sweep(Circle(1), lambda x: np.zeros((len(x), 2)), Circle(1), lambda x: np.zeros((len(x), 2)),
                         -0.1), "required", ">= 0"),
    (lambda: shortest_cycle(Circle(1), lambda x: np.zeros((len(x), 2)), (10, 5), Circle(1),
                            lambda x: np.zeros((len(x), 2)), (0, 90), 0.1), "span_a", "start < end"),
])
def test_bad_input_names_field_and_rule(make, field, words):
    with pytest.raises(SpecError) as exc:
        make()
    assert exc.value.field == field
    assert words in exc.value.rule


def test_clearance_check_fails_with_per_pair_required_missing():
    t = np.array([0.0, 1.0])
    c = min_clearance(Circle(1), [[0, 0], [0, 0]], Circle(1), [[5, 0], [5, 0]], t)
    assert isinstance(c, Clearance)
    with pytest.raises(SpecError) as exc:
        clearance_check({"a–b": c}, {"other": 1.0})
    assert exc.value.field == "required.a–b"
