"""The mechanism in motion (issue 24 item 5; docs/animation.md): MachineFrames against the
follower geometry written out here (docs/followers.md: a translating follower's point at
(e, √(R_b² − e²) + s), an oscillating arm's at D + L·e^{i(ψ₀ − s)}), the motion laws' closed forms,
the cam turned by δ·(φ − phase) (checked physically too: the roller touches the turned profile),
the linkage's joints; and the GIF/PNG/MP4 files decoded by Pillow."""
from __future__ import annotations

import copy
import math
import shutil

import numpy as np
import pytest
from PIL import Image

from cam_workbench.exporters.machine_animation import (animation_bytes, frame_png_bytes, picture_size, write_animation,
                                                       write_frame)
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import MissingDependency, SpecError
from cam_workbench.generators.linkage import FourBar, Lever
from cam_workbench.generators.machine import machine_from_dict
from cam_workbench.generators.machine.frames import machine_frames, turn_angles
from cam_workbench.generators.spec.examples import OSCILLATING_SPEC_DICT

DEG = math.pi / 180.0
H = 20.0                                     # the pusher's harmonic lift [mm]
RB, E, RR = 40.0, 6.0, 8.0                   # the sorter's prime radius, offset, roller


def harmonic_program(x_deg: np.ndarray) -> np.ndarray:
    """Rise H over 0–120° and return over 180–300°, s = H/2·(1 − cos πt), dwells between."""
    x = np.mod(x_deg, 360.0)
    s = np.where(x < 120, H / 2 * (1 - np.cos(np.pi * x / 120)), H)
    s = np.where(x >= 180, H / 2 * (1 + np.cos(np.pi * np.clip(x - 180, 0, 120) / 120)), s)
    return np.where(x >= 300, 0.0, s)


def cycloidal_program(x_deg: np.ndarray, h: float = 15.0) -> np.ndarray:
    """OSCILLATING_SPEC_DICT's program: dwell 30°, cycloidal rise h over 120°, dwell 60°, return."""
    x = np.mod(x_deg, 360.0)
    t_up = np.clip((x - 30) / 120, 0, 1)
    t_dn = np.clip((x - 210) / 120, 0, 1)
    cyc = (lambda t: t - np.sin(2 * np.pi * t) / (2 * np.pi))  # noqa: E731
    return h * (cyc(t_up) - cyc(t_dn))


def pusher(direction: str, offset: float, linkage: dict | None = None) -> dict:
    spec = {"units": "mm", "cam": {"base_radius": RB, "thickness": 10.0, "bore_diameter": 12.0, "direction": direction},
            "follower": {"kind": "roller", "roller_radius": RR, "offset": offset},
            "motion": [{"kind": "rise", "angle": 120.0, "lift": H, "law": "harmonic"}, {"kind": "dwell", "angle": 60.0},
                       {"kind": "return", "angle": 120.0, "lift": H, "law": "harmonic"},
                       {"kind": "dwell", "angle": 60.0}],
            "pitch": {"segments": 72}, "material": {"allowable_stress": 2000.0}}
    if linkage:
        spec["linkage"] = linkage
    return spec


LEVER = {"kind": "lever", "ratio": 1.5, "pivot_x": 0.0, "pivot_y": 90.0, "direction": 90.0}
FOUR_BAR = dict(kind="four_bar", ground=100.0, crank=40.0, coupler=90.0, rocker=60.0, crank_offset=60.0,
                pivot_x=60.0, pivot_y=0.0)
PLATE = [[-12.0, 0.0], [12.0, 0.0], [12.0, 6.0], [-12.0, 6.0]]


@pytest.fixture(scope="module")
def machine():
    osc = copy.deepcopy(OSCILLATING_SPEC_DICT)
    osc["cam"].pop("speed_rpm")
    osc["linkage"] = FOUR_BAR
    data = {"machine": {"name": "test station", "speed_rpm": 60.0},
            "cam": [{"name": "pusher", "phase": 30.0, "spec": pusher("ccw", 0.0, LEVER),
                     "tool": {"label": "plate", "polygon": PLATE}},
                    {"name": "sorter", "phase": 200.0, "spec": pusher("cw", E), "tool": {"circle": {"radius": 5.0}}},
                    {"name": "rocker", "phase": 90.0, "spec": osc}]}
    m = machine_from_dict(data)
    return m, [design_cam(c.spec) for c in m.cams]


@pytest.fixture(scope="module")
def frames(machine):
    m, designs = machine
    return machine_frames(m, designs, np.arange(0.0, 360.0, 7.5))


def cplx(a: np.ndarray) -> np.ndarray:
    return a[..., 0] + 1j * a[..., 1]


def test_cam_angle_and_lift(frames):
    phi = frames.machine_angle
    for cam, phase, law in zip(frames.cams, (30.0, 200.0, 90.0), (harmonic_program, harmonic_program,
                                                                  cycloidal_program)):
        x = np.mod(phi - phase, 360.0)
        assert np.allclose(cam.cam_angle, x, atol=1e-12)
        assert np.allclose(cam.lift, law(x), atol=1e-9)


def test_translating_roller_centre_on_the_follower_line(frames):
    """Roller centre = axis + (e, √(R_b² − e²) + s(φ − phase)) for both senses."""
    phi = frames.machine_angle
    for cam, phase, e in ((frames.cams[0], 30.0, 0.0), (frames.cams[1], 200.0, E)):
        s = harmonic_program(phi - phase)
        want = cam.centre + np.stack([np.full_like(s, e), math.sqrt(RB * RB - e * e) + s], axis=-1)
        assert np.allclose(cam.point, want, atol=1e-9)
        assert cam.roller_radius == RR
        assert cam.roles == ("stem",)
        assert np.allclose(cam.segments[:, 0, 0], want, atol=1e-9)     # the stem starts at the roller centre
        assert np.allclose(cam.segments[:, 0, 1, 0], want[:, 0], atol=1e-9)   # and is vertical


def test_oscillating_roller_on_its_arm(frames):
    """A = D + L·e^{i(ψ₀ − s)}, cos ψ₀ = (R_b² − d² − L²)/(2dL), D = (d, 0) (docs/followers.md)."""
    cam = frames.cams[2]
    d, L, rb = 60.0, 45.0, 40.0
    psi0 = math.acos((rb * rb - d * d - L * L) / (2 * d * L))
    s = cycloidal_program(frames.machine_angle - 90.0) * DEG
    a = d + L * np.exp(1j * (psi0 - s))
    assert np.allclose(cplx(cam.point - cam.centre), a, atol=1e-9)
    assert np.allclose(cplx(cam.pivot - cam.centre), d, atol=1e-12)
    assert cam.roles == ("arm",)


@pytest.mark.parametrize("k", [0, 1, 2])
def test_outline_turns_with_the_cam(frames, machine, k):
    """outline(φ) = Rot(δ(φ − phase))·profile + axis, and = Rot(δφ)·(outline(0) − axis) + axis."""
    m, designs = machine
    cam, design = frames.cams[k], designs[k]
    delta = 1 if m.cams[k].spec.cam.direction == "ccw" else -1
    _, prof = design.profile.sample(8)
    assert np.allclose(cam.profile[:len(prof)], prof[:, :2], atol=1e-12)
    c0 = cplx(cam.centre)
    turn = np.exp(1j * delta * (frames.machine_angle - m.cams[k].phase) * DEG)
    assert np.max(np.abs(cplx(cam.outline) - (turn[:, None] * cplx(cam.profile)[None, :] + c0))) < 1e-9
    at0 = cplx(cam.outline[0]) - c0                                  # machine angle 0
    by = np.exp(1j * delta * frames.machine_angle * DEG)
    assert np.max(np.abs(cplx(cam.outline) - c0 - by[:, None] * at0[None, :])) < 1e-9


@pytest.mark.parametrize("k", [0, 1, 2])
def test_roller_touches_the_turned_profile(frames, k):
    """The turned outline passes the roller at its radius (a wrong rotation sense or phase would
    not): the nearest outline vertex is R_r away, to the sampling's chord."""
    cam = frames.cams[k]
    dist = np.abs(cplx(cam.outline) - cplx(cam.point)[:, None]).min(axis=1)
    assert np.all(np.abs(dist - cam.roller_radius) < 0.02), np.abs(dist - cam.roller_radius).max()


def test_lever_joints_and_tool(frames):
    """The lever on the stem x = 0: tool = pivot + 1.5·s·(cos 90°, sin 90°), pivot (0, 90); the stem
    pushes it at (0, 90 + s) (the foot of the pivot on the stem); the fulcrum F solves
    T − F = 1.5·(I − F) at s = 0: F = (T₀ − 1.5·I₀)/(1 − 1.5) = (0, 90); placed at the cam's axis;
    the plate carried to the tool point, unturned."""
    cam = frames.cams[0]
    s = harmonic_program(frames.machine_angle - 30.0)
    pivot = cam.centre + np.array([0.0, 90.0])
    tool = pivot + np.stack([0 * s, 1.5 * s], axis=-1)
    assert np.allclose(cam.joints["input"], pivot + np.stack([0 * s, s], axis=-1), atol=1e-9)
    assert np.allclose(cam.joints["fulcrum"], pivot, atol=1e-9)
    assert np.allclose(cam.joints["tool"], tool, atol=1e-9)
    ref = Lever(1.5, False, (0.0, 90.0), 90.0 * DEG).on_follower((0.0, RB), 90.0 * DEG).joints(s)
    for name, pts in ref.items():
        assert np.allclose(cam.joints[name], pts + cam.centre, atol=1e-9)
    assert cam.links == (("input", "fulcrum"), ("fulcrum", "tool"))
    assert np.allclose(cam.tool_point, tool, atol=1e-9)
    plate = np.array(PLATE + PLATE[:1])
    assert np.allclose(cam.tool_outline, tool[:, None, :] + plate[None], atol=1e-9)


def test_four_bar_joints(frames):
    cam = frames.cams[2]
    q = cycloidal_program(frames.machine_angle - 90.0) * DEG
    ref = FourBar(100.0, 40.0, 90.0, 60.0, 60.0 * DEG, 1, (60.0, 0.0)).joints(q)
    assert set(cam.joints) == set(ref)
    for name, pts in ref.items():
        assert np.allclose(cam.joints[name], pts + cam.centre, atol=1e-9)
    # the links join the joints: the coupler keeps its length b = 90 in every frame
    assert ("crank_joint", "rocker_joint") in cam.links
    assert np.allclose(np.hypot(*(cam.joints["crank_joint"] - cam.joints["rocker_joint"]).T), 90.0, atol=1e-9)


def test_tool_without_linkage_rides_the_roller(frames):
    cam = frames.cams[1]
    assert cam.joints == {} and cam.links == ()
    assert np.allclose(cam.tool_point, cam.point, atol=1e-12)
    assert np.allclose(np.abs(cplx(cam.tool_outline) - cplx(cam.point)[:, None]), 5.0, atol=1e-9)


def test_row_layout_and_bounds(frames):
    """The axes on y = 0, left to right, the cams' boxes apart; every point inside the bounds."""
    boxes = np.array([c.box() for c in frames.cams])
    centres = np.array([c.centre for c in frames.cams])
    assert np.all(centres[:, 1] == 0.0) and centres[0, 0] == 0.0
    assert np.all(boxes[1:, 0] > boxes[:-1, 2])
    x0, y0, x1, y1 = frames.bounds
    assert x0 < boxes[:, 0].min() and y0 < boxes[:, 1].min() and x1 > boxes[:, 2].max() and y1 > boxes[:, 3].max()


def test_positions_given(machine):
    m, designs = machine
    at = [(0.0, 0.0), (0.0, 200.0), (250.0, -40.0)]
    f = machine_frames(m, designs, [0.0, 45.0], positions=at)
    assert np.allclose([c.centre for c in f.cams], at)
    with pytest.raises(SpecError, match="positions"):
        machine_frames(m, designs, [0.0], positions=at[:2])
    with pytest.raises(SpecError, match="designs"):
        machine_frames(m, designs[:2], [0.0])


# ---- files --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def small(machine):
    m, designs = machine
    return machine_frames(m, designs, turn_angles(30.0))


def test_gif_decodes(small, tmp_path):
    calls = []
    path = write_animation(small, tmp_path / "m.gif", fps=10, width_px=480,
                           progress=lambda d, t, w: calls.append((d, t)))
    assert calls == [(i + 1, 12) for i in range(12)]
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 12
        assert im.size == picture_size(small, 480) and im.size[0] == 480
        im.seek(0)
        first = np.asarray(im.convert("RGB"))
        im.seek(3)
        other = np.asarray(im.convert("RGB"))
    assert first.shape == other.shape and np.mean(np.any(first != other, axis=-1)) > 0.005


def test_same_frames_same_bytes(small):
    assert animation_bytes(small, "gif", width_px=320) == animation_bytes(small, "gif", width_px=320)


def test_still_frame(small, tmp_path):
    path = write_frame(small, 2, tmp_path / "still.png", width_px=480)
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size == picture_size(small, 480)
    assert frame_png_bytes(small, 2, width_px=480) == path.read_bytes()
    with pytest.raises(SpecError, match="frame"):
        frame_png_bytes(small, 12)


def test_bad_file_names_write_nothing(small, tmp_path):
    with pytest.raises(SpecError, match=r"\.gif or \.mp4"):
        write_animation(small, tmp_path / "m.avi")
    with pytest.raises(SpecError, match="--animation"):
        animation_bytes(small, "webm")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not on the PATH: the MP4 writer "
                                                             "(matplotlib's FFMpegWriter) needs it")
def test_mp4(small, tmp_path):
    path = write_animation(small, tmp_path / "m.mp4", fps=6, width_px=320)
    data = path.read_bytes()
    assert data[4:8] == b"ftyp" and len(data) > 1000


def test_mp4_without_ffmpeg_names_the_option(small, tmp_path, monkeypatch):
    """Where ffmpeg is not on the PATH (the PATH an empty folder), whether or not this machine has it."""
    (tmp_path / "empty").mkdir()
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    tmp_path = tmp_path / "empty"
    with pytest.raises(MissingDependency, match="--animation mp4"):
        write_animation(small, tmp_path / "m.mp4")
    assert list(tmp_path.iterdir()) == []


# ---- one model of the tool: the animation draws the clearance check's poses ----------------------
def _drawn_equals_clearance_poses(m, frames):
    """Every cam's drawn tool point minus its display offset, and its tool angle, are
    tools.tool_drive's poses at every frame's machine angle (the clearance check's model)."""
    from cam_workbench.generators.machine import tool_drive

    for cam, fc in zip(m.cams, frames.cams):
        if fc.tool_point is None:
            continue
        poses = tool_drive(cam.name, cam.spec, cam.phase, None, cam.tool).at_machine(frames.machine_angle)
        assert np.max(np.abs(fc.tool_point - fc.centre - poses.positions)) < 1e-12, cam.name
        want = np.zeros(len(frames)) if poses.angles is None else poses.angles
        assert np.max(np.abs(fc.tool_angle - want)) < 1e-12, cam.name


def test_frames_tool_is_the_clearance_tool(frames, machine):
    _drawn_equals_clearance_poses(machine[0], frames)


def test_example_frames_tool_is_the_clearance_tool():
    from cam_workbench.generators.machine import example_machine_dict

    m = machine_from_dict(example_machine_dict("three_cams"))
    f = machine_frames(m, [design_cam(c.spec) for c in m.cams], turn_angles(5.0))
    assert len(f) == 72
    _drawn_equals_clearance_poses(m, f)


def test_example_linkages_are_attached_to_their_followers():
    """The example machine: the pusher's lever bar starts on its stem (the input point's x is the
    roller centre's, and it rises with it); the gripper's crank pivot is its arm's pivot and, at
    zero lift, the crank joint lies on the arm (on the segment pivot → roller centre); the
    lifter's pad sits on the face, one pad radius above the face's contact height."""
    from cam_workbench.generators.machine import example_machine_dict

    m = machine_from_dict(example_machine_dict("three_cams"))
    f = machine_frames(m, [design_cam(c.spec) for c in m.cams], turn_angles(5.0))
    pusher, gripper, lifter = f.cams
    assert np.allclose(pusher.joints["input"][:, 0], pusher.point[:, 0], atol=1e-9)
    assert np.allclose(pusher.joints["input"][:, 1] - pusher.point[:, 1],
                       pusher.joints["input"][0, 1] - pusher.point[0, 1], atol=1e-9)
    assert pusher.links == (("input", "fulcrum"), ("fulcrum", "tool"))
    assert np.allclose(gripper.joints["crank_pivot"], gripper.pivot, atol=1e-9)
    zero = np.flatnonzero(np.abs(gripper.lift) < 1e-12)
    assert zero.size
    arm = cplx(gripper.point[zero]) - cplx(gripper.pivot[zero])
    crank = cplx(gripper.joints["crank_joint"][zero]) - cplx(gripper.pivot[zero])
    assert np.allclose(np.imag(crank * np.conj(arm)) / np.abs(arm), 0.0, atol=0.01)   # mm off the arm
    assert np.all(np.abs(crank) < np.abs(arm)) and np.all(np.real(crank * np.conj(arm)) > 0)
    face_y = lifter.segments[:, list(lifter.roles).index("face"), 0, 1]
    assert np.allclose(lifter.tool_point[:, 1] - face_y, 10.0, atol=1e-9)
    assert np.allclose(lifter.tool_point[:, 0], lifter.centre[0], atol=1e-9)


def test_default_tool_rides_the_translating_roller(frames):
    """The sorter (cw, offset e, no linkage, no origin/direction): the tool point is the roller
    centre (e, √(R_p² − e²) + s) in the cam's frame, R_p = R_b here (the base_radius is the prime
    radius for a roller: docs/followers.md), unturned."""
    cam = frames.cams[1]
    s = harmonic_program(frames.machine_angle - 200.0)
    want = np.stack([np.full_like(s, E), math.sqrt(RB * RB - E * E) + s], axis=-1)
    assert np.max(np.abs(cam.tool_point - cam.centre - want)) < 1e-9
    assert np.all(cam.tool_angle == 0.0)


def _one_cam(spec: dict, tool: dict, phase: float = 40.0):
    m = machine_from_dict({"machine": {"name": "one", "speed_rpm": 60.0},
                           "cam": [{"name": "c", "phase": phase, "spec": spec, "tool": tool}]})
    f = machine_frames(m, [design_cam(m.cams[0].spec)], turn_angles(15.0))
    return m, f


def test_default_tool_rides_the_oscillating_roller():
    """An arm without linkage: the tool point is the roller centre D + L·e^{i(ψ₀ − s)}, cos ψ₀ =
    (R_b² − d² − L²)/(2dL), and the tool turns with the arm by −s."""
    osc = copy.deepcopy(OSCILLATING_SPEC_DICT)
    osc["cam"].pop("speed_rpm")
    m, f = _one_cam(osc, {"circle": {"radius": 4.0}})
    cam = f.cams[0]
    d, L, rb = 60.0, 45.0, 40.0
    psi0 = math.acos((rb * rb - d * d - L * L) / (2 * d * L))
    s = cycloidal_program(f.machine_angle - 40.0) * DEG
    assert np.max(np.abs(cplx(cam.tool_point - cam.centre) - (d + L * np.exp(1j * (psi0 - s))))) < 1e-9
    assert np.max(np.abs(cam.tool_angle + s)) < 1e-12
    assert np.allclose(cam.tool_point, cam.point, atol=1e-9)        # on the drawn roller
    _drawn_equals_clearance_poses(m, f)


def test_default_tool_on_the_translating_flat_face():
    """A translating flat face, offset e: the tool at the face's foot on the stem, (e, R_b + s)."""
    spec = pusher("ccw", 5.0)
    spec["follower"] = {"kind": "flat", "offset": 5.0, "face_width": 60.0}
    m, f = _one_cam(spec, {"circle": {"radius": 3.0}})
    cam = f.cams[0]
    s = harmonic_program(f.machine_angle - 40.0)
    want = np.stack([np.full_like(s, 5.0), RB + s], axis=-1)
    assert np.max(np.abs(cam.tool_point - cam.centre - want)) < 1e-9
    assert np.allclose(cam.tool_point, cam.segments[:, cam.roles.index("stem"), 0], atol=1e-9)   # the drawn foot
    _drawn_equals_clearance_poses(m, f)


def test_explicit_origin_direction_keep_their_meaning():
    """[cam.tool] origin/direction: origin + s·(cos, sin)(direction), not the follower's point."""
    m, f = _one_cam(pusher("ccw", 0.0), {"circle": {"radius": 3.0}, "origin": [10.0, -5.0], "direction": 30.0})
    cam = f.cams[0]
    s = harmonic_program(f.machine_angle - 40.0)
    want = np.array([10.0, -5.0]) + s[:, None] * np.array([math.cos(30 * DEG), math.sin(30 * DEG)])
    assert np.max(np.abs(cam.tool_point - cam.centre - want)) < 1e-9
    _drawn_equals_clearance_poses(m, f)
