"""docs/indexing.md runs as written, and the figures its prose quotes are the ones its code
computes (the design's summary, the sizing's summary, the laws' characteristic values)."""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from cam_workbench.generators.motion.characteristics import law_characteristics

DOC = Path(__file__).resolve().parents[1] / "docs" / "indexing.md"


@pytest.fixture(scope="module")
def ran() -> tuple[str, dict]:
    text = DOC.read_text(encoding="utf-8")
    scope: dict = {}
    for block in re.findall(r"```python\n(.*?)```", text, flags=re.S):
        exec(compile(block, str(DOC), "exec"), scope)  # noqa: S102 — the page's own examples
    return text, scope


def near(quoted: str, value: float) -> bool:
    """``quoted`` (as printed, e.g. "0.333" or "1.20") is ``value`` rounded to its digits."""
    digits = len(quoted.split(".")[1]) if "." in quoted else 0
    return abs(float(quoted) - value) <= 0.5 * 10 ** -digits * (1 + 1e-9)


def test_the_sizing_figures_are_the_examples(ran):
    text, scope = ran
    s = scope["s"].summary()
    para = " ".join(text.split("For the example above:")[1].split())
    want = {
        r"index time ([\d.]+) s": s["index_time_s"],
        r"peak output acceleration ([\d.]+) rad/s²": s["output_acceleration_peak_rad_s2"],
        r"peak output torque ([\d.]+) N·m": s["output_torque_peak_Nm"],
        r"peak input torque ([\d.]+) N·m": s["input_torque_peak_Nm"],
        r"peak input power ([\d.]+) W": s["input_power_peak_W"],
        r"peak normal load ([\d.]+) kN": s["normal_force_peak_N"] / 1e3,
        r"peak Hertz stress ([\d.]+) GPa": s["contact_stress_peak_Pa"] / 1e9,
        r"L10 ([\d.]+)·10⁸ roller revolutions": s["l10_million_rev"] * 1e6 / 1e8,
        r"\(([\d.]+)·10⁵ h\)": s["l10_hours"] / 1e5,
    }
    for pattern, value in want.items():
        m = re.search(pattern, para)
        assert m, pattern
        assert near(m.group(1), value), (pattern, m.group(1), value)


def test_the_design_figures_are_the_examples(ran):
    text, scope = ran
    d = scope["d"].summary()
    table = " ".join(text.split("Default design")[1].split("## The drive")[0].split())
    m = re.search(r"clearance of the rollers a cam does not hold \| ([\d.]+) mm", table)
    assert m and near(m.group(1), d["clearance_mm"])
    m = re.search(r"over the index \| ([\d.]+)° at θ = ([\d.]+)°", table)
    assert m and near(m.group(1), d["max_driving_pressure_angle_deg"])
    assert near(m.group(2), d["max_driving_pressure_angle_at_deg"])
    m = re.search(r"\| ([\d.]+) mm · ([\d.]+) mm \|", table)
    cam0 = d["per_cam"][0]
    assert m and near(m.group(1), cam0["dwell_radius_mm"]) and near(m.group(2), cam0["crossover_radius_mm"])


@pytest.mark.parametrize("law, row", [("cycloidal", "cycloidal"), ("harmonic", "simple harmonic"),
                                      ("modified_sine", "modified sine"), ("modified_trapezoid", "modified trapezoid"),
                                      ("poly345", "3-4-5 polynomial"), ("poly4567", "4-5-6-7 polynomial")])
def test_the_characteristics_table(ran, law, row):
    text, _ = ran
    line = next(ln for ln in text.splitlines() if ln.startswith(f"| {row} |"))
    cells = [c.strip().split(" ")[0] for c in line.strip("|").split("|")[1:]]
    c = law_characteristics(law)
    for quoted, value in zip(cells, (c.C_v, c.C_a, c.C_j, c.torque_index, c.Q)):
        if quoted == "∞":
            assert math.isinf(value)
        else:
            assert near(quoted, value), (row, quoted, value)


def test_the_body_figures_are_the_examples(ran):
    text, scope = ran
    body = scope["body"]
    para = " ".join(text.split("### The cams as a body")[1].split("## The drive")[0].split())
    assert re.search(r"For the default design: (\d+) nodes per flank", para).group(1) == str(
        body.geometry.extra["flank_nodes"][0][0])
    assert near(re.search(r"fit error ([\d.e-]+) mm", para).group(1).replace("e-5", ""), body.fit_error * 1e5)
    assert near(re.search(r"volume ([\d ]+\.\d+) mm³", para).group(1).replace(" ", ""), body.volume)


def test_the_spatial_figures_are_the_examples(ran):
    text, scope = ran
    table = text.split("## The barrel and globoidal indexers")[1].split("## The drive")[0]
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.strip().strip("|").split("|")[1:]]
            for ln in table.splitlines() if ln.startswith("| ")}
    for col, design in enumerate((scope["barrel"], scope["globoid"])):
        s = design.summary()
        drive = re.match(r"([\d.]+)° at θ = ([\d.]+)°", rows["largest pressure angle of the driving contact line"][col])
        assert near(drive.group(1), s["max_driving_pressure_angle"]["value_deg"])
        assert near(drive.group(2), s["max_driving_pressure_angle"]["at_deg"])
        margin = re.match(r"([\d.]+) at θ = ([\d.]+)°", rows["smallest regularity margin"][col])
        assert near(margin.group(1), s["min_regularity_margin"]["value_1"])
        assert near(margin.group(2), s["min_regularity_margin"]["at_deg"])
        rib = re.match(r"([\d.]+) mm at θ = ([\d.]+)°", rows["thinnest rib"][col])
        assert near(rib.group(1), s["min_rib_thickness"]["value_mm"])
        assert near(rib.group(2), s["min_rib_thickness"]["at_deg"])


def test_the_surface_figures_are_the_examples(ran):
    from cam_workbench.generators.bodies.indexing.spatial import GloboidalIndexer, design_globoidal
    from cam_workbench.generators.bodies.indexing.spatial_surfaces import flank_surfaces

    text, scope = ran
    table = text.split("### The flanks as B-spline surfaces")[1].split("Not yet:")[0]
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.strip().strip("|").split("|")[1:]]
            for ln in table.splitlines() if ln.startswith("| ") and "µm" in ln}
    barrel = scope["surfaces"].summary()["flanks"]
    globoid = flank_surfaces(design_globoidal(GloboidalIndexer())).summary()["flanks"]
    for name, flank in (("barrel, side +1 (holds)", barrel[0]), ("barrel, side −1 (drives)", barrel[1]),
                        ("globoidal, each side", globoid[0]), ("globoidal, each side", globoid[1])):
        nodes, dist, normal = rows[name]
        assert nodes == f"{flank['nodes_tau']} × {flank['nodes_t']}"
        assert near(dist.split()[0], flank["max_error_mm"] * 1e3)
        assert near(normal.split()[0], flank["max_normal_error_mm"] * 1e3)


def test_the_spatial_drive_figures_are_the_examples(ran):
    """The barrel's hand-over spike the page quotes: the peak Hertz stress, and the peak where the
    loaded line is at least 5 mm long, at the page's load (60 rpm, 2 kg·m², 5 N·m, 18 mm, 20 kN)."""
    import numpy as np

    from cam_workbench.generators.bodies.indexing.spatial_drive import spatial_contacts, spatial_drive

    text, scope = ran
    para = " ".join(text.split("`spatial_drive(design, …)`")[1].split("`parallel_drive` sizes")[0].split())
    barrel = scope["barrel"]
    s = spatial_drive(barrel, input_speed=60, inertia=2.0, friction_torque=5.0, roller_width=18.0,
                      roller_rating=20_000.0)
    c = spatial_contacts(barrel)
    length = np.where(s.torque_out >= 0, c.forward.length, c.holding.length)
    m = re.search(r"puts it on ([\d.]+) mm of roller for one sample \(Hertz (\d+) MPa there, (\d+) MPa elsewhere\)", para)
    assert m
    i = int(np.argmax(s.contact_stress))
    assert near(m.group(1), length[i]) and near(m.group(2), s.contact_stress[i] / 1e6)
    assert near(m.group(3), np.max(np.where(length >= 5.0, s.contact_stress, 0.0)) / 1e6)


def test_the_optimiser_figures_are_the_examples(ran):
    text, scope = ran
    para = " ".join(text.split("### Optimising it")[1].split("## The barrel")[0].split())
    s = scope["best"].summary()
    m = re.search(r"outer radius ([\d.]+) → ([\d.]+) mm \(C ([\d.]+) mm at its lower bound, R_p ([\d.]+) mm, "
                  r"r_r ([\d.]+) mm\), pressure angle ([\d.]+)° → ([\d.]+)°, (\d+) designs", para)
    assert m, para
    v = s["variables_mm"]
    for quoted, value in zip(m.groups(), (s["start_value"], s["value"], v["centre_distance"], v["pitch_radius"],
                                          v["roller_radius"], s["start"]["constraints"]["pressure_angle_deg"],
                                          s["constraints"]["pressure_angle_deg"], s["evaluations"])):
        assert near(quoted, value), (quoted, value)
    assert s["verdict"] == "converged" and v["centre_distance"] == pytest.approx(s["bounds_mm"]["centre_distance"][0])


def test_the_gcode_figures_are_the_examples(ran):
    from cam_workbench.exporters.gcode_indexer import indexer_programs

    text, scope = ran
    para = " ".join(text.split("### Its G-code")[1].split("### Optimising it")[0].split())
    m = re.search(r"Default design, 6 mm tool: biarc error ([\d.e-]+) mm, the written path \(4-decimal "
                  r"coordinates\) ([\d.e-]+) mm", para)
    assert m
    programs = indexer_programs(scope["d"], scope["body"], 6.0)
    assert near(m.group(1).replace("e-5", ""), max(p.biarc_error for p in programs) * 1e5)
    assert near(m.group(2).replace("e-5", ""), max(p.path_error for p in programs) * 1e5)
