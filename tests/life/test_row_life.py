"""Lives of a shaft's rows from a run: beam statics, ISO 281 by hand, refusals and the CLI."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.life.bearing_life import bearing_lives
from pinwind.life.row_life import row_lives
from pinwind.loads.hub_loads import constant_hub_load
from pinwind.model.gearbox import loads
from tests.analysis.test_bearing_rows import A, B, _rows, shaft_on_rows
from tests.test_cli import run as run_cli

RPM = 2 * math.pi / 60
SPEED_RPM = 30.0
WEIGHT, MOMENT, OVERHANG = 1.0e5, 2.0e5, -1.5
#: Row data added to both rows: size (D d B) 300/200/60 mm (d_m = 250 mm), C_u = 100 kN,
#: VG 220 with ν100 = 19 mm²/s at 60 °C, normal cleanliness.
ROW_DATA = (
    'rating_c_kN="1000" size_mm="300 200 60" fatigue_limit_kN="100" lubricant_vg="220" '
    'temperature_C="60" viscosity_100C_cSt="19"/>'
)


def shaft_text() -> str:
    return shaft_on_rows(_rows(k=1e11)).replace('rating_c_kN="1000"/>', ROW_DATA)


def run_shaft(text: str, *, log=None, moment: float = MOMENT, point: float = OVERHANG):
    gb = loads(text, path="shaft.urdf")
    load = constant_hub_load(
        "shaft", [0, 0, -WEIGHT, 0, moment, 0], point=(0, 0, point), up=(0, 1, 0)
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb, duration=0.02, dt=1e-3, hub_loads=[load], speeds={"shaft": SPEED_RPM * RPM},
            log=log,
        )  # fmt: skip
    return res, gb


def statics() -> tuple[float, float]:
    """Radial reactions of rows A and B (tests/analysis/test_bearing_rows.py's beam statics)."""
    r_b = (MOMENT + OVERHANG * WEIGHT - A * WEIGHT) / (B - A)
    return WEIGHT - r_b, r_b


def walther(nu40: float, nu100: float, t_c: float) -> float:
    """ν [mm²/s] at t_c [°C] on ASTM D341's line through (40 °C, ν40) and (100 °C, ν100)."""

    def w(nu: float) -> float:
        return math.log10(math.log10(nu + 0.7))

    b = (w(nu40) - w(nu100)) / math.log10(373.15 / 313.15)
    value = w(nu40) - b * math.log10((t_c + 273.15) / 313.15)
    return 10 ** (10**value) - 0.7


def test_rows_get_basic_modified_and_reference_lives_from_their_share_of_the_moment():
    res, gb = run_shaft(shaft_text())
    lives = {r.name: r for r in row_lives(res, gb)}
    r_a, r_b = statics()
    # the bending moment loads the rows: without it (M = 0) the reactions would differ
    assert abs(r_a - (WEIGHT - (OVERHANG * WEIGHT - A * WEIGHT) / (B - A))) > 0.1 * abs(r_a)
    per_hour = SPEED_RPM * 60.0
    for name, reaction in (("A", r_a), ("B", r_b)):
        life = lives[name]
        p = abs(reaction)  # no axial load: P = F_r for both types
        assert_allclose(life.equivalent_load, p, rtol=1e-6)
        l10 = (1e6 / p) ** (10 / 3)
        assert_allclose(life.l10, l10, rtol=2e-5)
        assert_allclose(life.l10h, l10 * 1e6 / per_hour, rtol=1e-4)
        # ISO 281 modified life by hand: ν at 60 °C, ν₁ at 30 r/min and d_m = 250 mm, κ,
        # e_C = 0.7 (normal cleanliness, d_m ≥ 100 mm), a_ISO in κ's regime.
        nu = walther(220.0, 19.0, 60.0)
        nu1 = 45000 * SPEED_RPM**-0.83 * 250.0**-0.5
        kappa = nu / nu1
        assert 0.4 <= kappa < 1.0, kappa
        x = 0.7 * 100e3 / p
        a_iso = min(0.1 * (1 - (1.5859 - 1.2348 / kappa**0.19087) * x**0.4) ** -9.185, 50.0)
        assert_allclose(life.kappa_mean, kappa, rtol=1e-9)
        assert_allclose(life.a_iso, a_iso, rtol=1e-6)
        assert_allclose(life.lnm, a_iso * l10, rtol=2e-5)
        # zero clearance, radial load only: ISO/TS 16281's calibration case (within 2 %)
        assert_allclose(life.l10r, l10, rtol=0.02)
        assert_allclose(np.degrees(life.load_zone_min), 180.0, atol=1e-6)


def test_a_whole_bearing_carrying_a_moment_is_refused_with_the_reason():
    rigid = shaft_text()
    start = rigid.index("<bearing joint")
    end = rigid.index("</bearing>") + len("</bearing>")
    rigid = rigid[:start] + '<bearing joint="shaft" type="spherical_roller" rating_c_kN="1000"/>'
    rigid += shaft_text()[end:]
    res, gb = run_shaft(rigid)
    (life,) = bearing_lives(res, gb)
    assert life.rated and math.isnan(life.l10)
    assert "tilting moment" in life.refused and "<row>" in life.refused
    assert life.as_dict()["l10_h"] is None
    # the same bearing loaded through its centre carries no moment: rated
    res, gb = run_shaft(rigid, moment=0.0, point=0.0)
    (life,) = bearing_lives(res, gb)
    assert not life.refused
    assert_allclose(life.l10, (1e6 / WEIGHT) ** (10 / 3), rtol=1e-6)


@pytest.fixture(scope="module")
def shaft_log(tmp_path_factory):
    """A logged run of the two-row shaft (shared by the command's tests)."""
    log = tmp_path_factory.mktemp("life") / "shaft.mcap"
    run_shaft(shaft_text(), log=log)
    return log


def test_life_command_gives_every_row_from_a_log(shaft_log):
    log = shaft_log
    out = run_cli("life", str(log), "--json")
    assert out.returncode == 0, out.stderr
    got = {r["row"]: r for r in json.loads(out.stdout)["rows"]}
    r_a, r_b = statics()
    assert_allclose(got["A"]["l10_million_rev"], (1e6 / abs(r_a)) ** (10 / 3), rtol=2e-5)
    assert_allclose(got["B"]["l10_million_rev"], (1e6 / abs(r_b)) ** (10 / 3), rtol=2e-5)
    table = run_cli("life", str(log))
    assert table.returncode == 0, table.stderr
    lines = [line.strip() for line in table.stdout.splitlines()]
    shaft = lines.index("shaft")  # the bearing on a line of its own, then its rows
    assert lines[shaft + 1].split()[0] == "A" and "L10rh" in table.stdout


def test_life_table_of_the_5mw_gearbox_fits_80_columns_with_units_and_whole_cells(tmp_path):
    # 24 rows named stage1_planet1/PL-A, ... in ten columns: at a pipe's 80 columns no cell
    # may be cut short ("779…") and the load columns keep their unit (rich took "[kN]" for a
    # style and dropped it).
    from tests.conftest import MODELS

    log = tmp_path / "nrel.mcap"
    gearbox = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    res = pinwind.simulate(gearbox, duration=2e-3, dt=1e-4, log=log, progress=False)
    out = run_cli("life", str(log))
    assert out.returncode == 0, out.stderr
    title = out.stdout.index("Rolling bearings (rows)")
    table = out.stdout[title : out.stdout.index("P<Pmin: ")].splitlines()
    assert max(len(line) for line in table) <= 80 and "…" not in "".join(table)
    assert table[1].split().count("P") == 1 and table[2].split().count("[kN]") == 2
    rows = row_lives(res, gearbox)
    assert len(rows) == 24
    cells = [line.split() for line in table]
    for r in rows:  # each row's P [kN] and L10h as the command rounds them, whole
        assert [r.name, f"{r.equivalent_load / 1e3:.4g}", f"{r.l10h:.3g}"] in (
            [c[0], c[2], c[3]] for c in cells if len(c) > 3
        ), r.name


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('lubricant_vg="220"', 'lubricant_vg="300"', "not an ISO 3448 viscosity grade"),
        (
            'fatigue_limit_kN="100"',
            'fatigue_limit_kN="100" radial_clearance_mm="-0.02"',
            "a negative clearance is a preload",
        ),
        (
            'fatigue_limit_kN="100"',
            'fatigue_limit_kN="1200"',
            "is not below the dynamic load rating C = 1000 kN",
        ),
    ],
)
def test_bad_bearing_life_data_is_one_message_and_exit_2(tmp_path, shaft_log, old, new, message):
    log = shaft_log
    lines = shaft_text().splitlines(keepends=True)
    row_a = next(i for i, line in enumerate(lines) if 'name="A"' in line)
    lines[row_a] = lines[row_a].replace(old, new)
    model = tmp_path / "bad.urdf"
    model.write_text("".join(lines))
    out = run_cli("life", str(log), "--model", str(model))
    assert out.returncode == 2
    errors = out.stderr.strip().splitlines()
    assert len(errors) == 1 and message in errors[0] and '<row name="A">' in errors[0], out.stderr


@pytest.mark.parametrize("clearance_mm", [0.0, 0.02])
def test_grouping_the_loads_in_cells_keeps_the_reference_life(clearance_mm):
    # A load turning through 60° and varying by ±40 % in size over 400 samples: the life from
    # the grouped loads against the one from every sample's own distribution.
    from pinwind.dynamics.load_distribution import distribute, reference_load
    from pinwind.life.life_sums import geometry_of
    from pinwind.life.row_life import rate_row
    from pinwind.model.bearing import bearing_rating
    from pinwind.model.bearing_life_data import life_data

    n = 400
    t = np.linspace(0.0, 1.0, n)
    angle = np.radians(60.0) * t
    size = 2e5 * (1.0 + 0.4 * np.sin(7 * t))
    load = np.zeros((n, 5))
    load[:, 0], load[:, 1] = size * np.cos(angle), size * np.sin(angle)
    load[:, 4] = 0.02 * size  # a tilting moment the rows carry
    attrs = {"size_mm": "300 200 60", "radial_clearance_mm": str(clearance_mm)}
    data = life_data(attrs, where="<row>", path="<test>")
    speed = np.full(n, 100 * RPM)
    life = rate_row(
        name="r", bearing="b", position=0.0,
        rating=bearing_rating("b.r", "cylindrical_roller", dynamic_load_rating=1e6),
        size=None, data=data, time=t, speed=speed, load=load,
    )  # fmt: skip
    geometry = geometry_of("cylindrical_roller", data, None)
    assert geometry is not None
    each = reference_load(geometry, distribute(geometry, load).slice_loads)
    w = np.full(n, 1.0)  # equal revolutions per sample but the ends' halves (trapezoid rule)
    w[[0, -1]] = 0.5
    p_eq = (np.sum(w * each ** (10 / 3)) / np.sum(w)) ** 0.3
    assert_allclose(life.reference_load, p_eq, rtol=2e-3)


def test_a_preloaded_rows_smallest_load_zone_is_its_own_not_capped_at_180():
    # A cylindrical row preloaded by c = −20 µm under a constant radial load F along u: every
    # sample's zone is 2 arccos(c/δ_r) > 180° (Harris and Kotzalas 2007 §7.3), δ_r solving
    # F = Σ K (δ_r cos ψ_j − c)₊^(10/9) cos ψ_j (bisection, independent of the Newton solve).
    from scipy.optimize import brentq

    from pinwind.life.life_sums import geometry_of
    from pinwind.life.row_life import rate_row
    from pinwind.model.bearing import bearing_rating
    from pinwind.model.bearing_life_data import life_data

    n, f, c = 20, 2.0e5, -20e-6
    load = np.zeros((n, 5))
    load[:, 0] = f
    attrs = {"size_mm": "300 200 60", "radial_clearance_mm": "-0.02", "preload": "true"}
    data = life_data(attrs, where="<row>", path="<test>")
    life = rate_row(
        name="r", bearing="b", position=0.0,
        rating=bearing_rating("b.r", "cylindrical_roller", dynamic_load_rating=1e6),
        size=None, data=data, time=np.linspace(0.0, 1.0, n), speed=np.full(n, 100 * RPM),
        load=load,
    )  # fmt: skip
    geometry = geometry_of("cylindrical_roller", data, None)
    assert geometry is not None
    k = geometry.slice_stiffness * geometry.slice_count
    psi = 2 * np.pi * np.arange(geometry.rollers) / geometry.rollers

    def excess(delta: float) -> float:
        d = np.maximum(delta * np.cos(psi) - c, 0.0)
        return float(np.sum(k * d ** (10 / 9) * np.cos(psi))) - f

    delta_r = brentq(excess, 0.0, 1e-2, xtol=1e-16)
    zone = 2 * math.acos(c / delta_r)
    assert zone > math.pi
    assert_allclose(life.load_zone, zone, rtol=1e-6)
    assert_allclose(life.load_zone_min, zone, rtol=1e-6)


def test_life_takes_the_reliability_in_percent_under_its_new_and_its_former_name(shaft_log):
    # ISO 281:2007 Table 12: a₁ = 1 at 90 %, 0.25 at 99 %; L_nm scales with a₁. The former name
    # --reliability took the same unit, percent, and still works.
    lnm = {}
    for options in ([], ["--reliability-percent", "99"], ["--reliability", "99"]):
        out = run_cli("life", str(shaft_log), "--json", *options)
        assert out.returncode == 0, out.stderr
        rows = {r["row"]: r for r in json.loads(out.stdout)["rows"]}
        lnm[" ".join(options)] = {name: r["lnm_million_rev"] for name, r in rows.items()}
        assert {r["reliability_percent"] for r in rows.values()} == {99.0 if options else 90.0}
        assert_allclose([r["a1"] for r in rows.values()], 0.25 if options else 1.0, atol=0.006)
    for name, at_90 in lnm[""].items():
        assert_allclose(lnm["--reliability-percent 99"][name], 0.25 * at_90, rtol=0.025)
        assert lnm["--reliability 99"][name] == lnm["--reliability-percent 99"][name]


@pytest.mark.parametrize(
    ("options", "named"),
    [
        # a fraction, the unit `rate --reliability` took: named with its percent
        (["--reliability-percent", "0.9"], "a fraction: 90 % is --reliability-percent 90"),
        (["--reliability-percent", "89.9"], "90 ≤ R ≤ 99.95 %"),
        (["--reliability-percent", "99.99"], "90 ≤ R ≤ 99.95 %"),
        (["--reliability", "0.99"], "--reliability 0.99: give a reliability R in percent, 90 ≤ R"),
        (["--reliability", "99", "--reliability-percent", "95"], "give one"),
    ],
)
def test_life_refuses_a_reliability_outside_iso_281_or_given_twice(shaft_log, options, named):
    out = run_cli("life", str(shaft_log), *options)
    assert out.returncode == 2, out.stderr
    (line,) = out.stderr.strip().splitlines()
    assert named in line and options[1] in line, line
