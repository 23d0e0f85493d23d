"""The page's SI units and their length unit L (docs/physics.md, "The page's SI units"):
every conversion goes both ways to the last bits, the CSV files in SI are the dimensionless
ones times the scales, a link written before L existed opens the run it showed, and a bad L
is refused with its name and range."""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from app.commit_rules import refusal_si
from app.explorer import Explorer
from app.export import trajectory_csv, transitions_csv
from app.solve.pool import solve
from app.state import (
    LENGTHS,
    MM_PER_M,
    SI_NAMES,
    ExplorerState,
    scene_values,
    si_units,
)

#: A conversion is one multiplication one way and one division back (each rounded to half
#: an ulp), and Oscillator.from_physical's F_N / k and v_dr / omega are one more each: a
#: few ulps of the value, never more.
ROUND_TRIP_RTOL = 8 * np.finfo(float).eps

#: State values the SI boxes convert, with a range of their dimensionless numbers that
#: keeps their SI values inside the state's bounds at any m, k, L drawn below.
CONVERTED = {"u_s": (0.05, 3.0), "belt_speed": (0.0, 0.6), "v0": (-1.5, 1.5),
             "t_end": (1.0, 300.0), "k_c0": (1.0, 2000.0), "k_e0": (1.0, 2000.0),
             "clearance": (-0.2, 0.8), "x0": (-1.5, 1.5), "limit_overlap": (0.001, 0.2)}


def _value(name: str):
    low, high = CONVERTED[name]
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@given(mass=st.floats(0.1, 10.0), stiffness=st.floats(10.0, 1000.0),
       length_unit=st.floats(1e-4, 1.0), name=st.sampled_from(sorted(CONVERTED)),
       data=st.data())
def test_si_to_dimensionless_to_si_is_the_same_number(mass, stiffness, length_unit, name,
                                                      data):
    """Each SI box's value, converted to the state's number and back, is itself; and the
    state's number read in SI and converted back is itself (to float precision)."""
    value = data.draw(_value(name))
    if name == "k_e0":
        state = ExplorerState(mass=mass, stiffness=stiffness, length_unit=length_unit,
                              k_c0=2000.0, k_e0=value)
    else:
        state = ExplorerState(mass=mass, stiffness=stiffness, length_unit=length_unit,
                              **{name: value})
    key = SI_NAMES[name][0]
    si = state.physical()[key]
    back = state.from_physical(**{key: si})[name]
    assert back == pytest.approx(value, rel=ROUND_TRIP_RTOL, abs=1e-300)
    again = ExplorerState(mass=mass, stiffness=stiffness, length_unit=length_unit,
                          **({"k_c0": 2000.0} if name == "k_e0" else {}), **{name: back})
    assert again.physical()[key] == pytest.approx(si, rel=ROUND_TRIP_RTOL, abs=1e-300)


@given(length_unit=st.floats(1e-4, 1.0), x=st.floats(-1.5, 1.5))
def test_a_length_in_mm_is_1e3_L_times_the_dimensionless_one(length_unit, x):
    """The independent reference: a length of x units of L metres is 1e3 L x mm."""
    state = ExplorerState(length_unit=length_unit, x0=x, units="SI")
    assert state.physical()["x0"] == pytest.approx(x * length_unit * 1e3, rel=ROUND_TRIP_RTOL,
                                                   abs=1e-300)
    assert state.scales().length == pytest.approx(length_unit * 1e3, rel=ROUND_TRIP_RTOL)


def test_a_new_length_unit_resizes_the_rig_and_keeps_the_scene():
    """The L box keeps the dimensionless scene: F_N, v_dr and every length scale with L
    (the same motion at another size), the seconds stay."""
    state = ExplorerState(**scene_values("7c"), units="SI")
    before = state.physical()
    values = state.from_physical(L=20.0)
    assert values == {"length_unit": 0.02}
    state.param.update(**values)
    after = state.physical()
    for key in ("normal_force", "belt_speed", "v0", "clearance", "x0"):
        assert after[key] == pytest.approx(2.0 * before[key], rel=ROUND_TRIP_RTOL), key
    assert after["t_end"] == before["t_end"] and after["k_c0"] == before["k_c0"]


def test_the_default_bench_rig_numbers():
    """The scenes' u_s = 1 is a 10 mm static deflection and F_N = 2 N on the 200 N/m
    spring (it was 1 m and 200 N); scene 7c's clearance 0.25 is 2.5 mm and its belt
    v = 0.1 runs at omega L v = 0.02 m/s."""
    phys = ExplorerState(**scene_values("7c"), units="SI").physical()
    omega = math.sqrt(200.0 / 0.5)
    assert phys["normal_force"] == pytest.approx(200.0 * 0.01 * 1.0, rel=ROUND_TRIP_RTOL)
    assert phys["clearance"] == pytest.approx(scene_values("7c")["clearance"] * 10.0,
                                              rel=ROUND_TRIP_RTOL)
    assert phys["belt_speed"] == pytest.approx(scene_values("7c")["belt_speed"] * omega * 0.01,
                                               rel=ROUND_TRIP_RTOL)


def _table(text: str) -> tuple[list[str], list[list[str]]]:
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith("#")]
    return rows[0], rows[1:]


#: The Scales factor of each CSV column, by the column's name before its unit.
COLUMN_FACTORS = {"t": "time", "x": "length", "xdot": "velocity", "contact_force": "force",
                  "overlap": "length", "v_before": "velocity", "v_after": "velocity",
                  "impulse": "impulse", "s": None}


@pytest.mark.parametrize("scene", ["5b", "7c", "10", "2b"])
@pytest.mark.parametrize("write", [trajectory_csv, transitions_csv])
def test_a_csv_in_si_divided_by_the_scales_is_the_dimensionless_csv(scene, write):
    sol = solve(scene_values(scene))
    scales = ExplorerState(units="SI", mass=0.7, stiffness=350.0, length_unit=0.004).scales()
    head_si, rows_si = _table(write(sol, scales).getvalue())
    head, rows = _table(write(sol).getvalue())
    assert len(rows_si) == len(rows) and len(head_si) == len(head)
    assert "x [mm]" in head_si or "overlap [mm]" in head_si
    for col, (name_si, name) in enumerate(zip(head_si, head, strict=True)):
        base = name.split(" [")[0]
        assert name_si.split(" [")[0] == base
        factor = COLUMN_FACTORS.get(base)
        for row_si, row in zip(rows_si, rows, strict=True):
            if factor is None or row[col] == "":
                assert row_si[col] == row[col]
                continue
            value = float(row_si[col]) / getattr(scales, factor)
            assert value == pytest.approx(float(row[col]), rel=ROUND_TRIP_RTOL, abs=1e-300)


def test_an_si_link_without_a_length_unit_opens_the_run_it_showed():
    """Before the length unit, an SI link read its lengths (and so its speeds and forces)
    in metres: it opens with L = 1 m, the same dimensionless run, lengths shown in mm."""
    ex = Explorer()
    assert ex.permalink.apply_query("scene=7c&units=SI&m=2&k=50&v=1.5") == []
    assert ex.state.length_unit == 1.0
    assert ex.state.belt_speed == pytest.approx(1.5 / 5.0, rel=ROUND_TRIP_RTOL)
    assert ex.state.clearance == scene_values("7c")["clearance"]
    assert ex.controls.sliders["clearance_si"].value == pytest.approx(
        scene_values("7c")["clearance"] * 1e3)
    # A link of the page names its L and gives it back.
    other = Explorer()
    assert other.permalink.apply_query(ex.permalink.query) == []
    assert other.state.length_unit == 1.0 and other.state.belt_speed == ex.state.belt_speed
    # With L = 10 mm a v_dr is a hundred times more units of L per unit of time.
    new = Explorer()
    assert new.permalink.apply_query("scene=7c&units=SI&m=2&k=50&v=0.015&L=0.01") == []
    assert new.state.belt_speed == pytest.approx(0.015 / (5.0 * 0.01), rel=ROUND_TRIP_RTOL)
    # A dimensionless link keeps the page's default L.
    plain = Explorer()
    plain.permalink.apply_query("scene=7c&v=0.2")
    assert plain.state.length_unit == 0.01


@pytest.mark.parametrize("text", ["0", "-0.01", "1e9", "nan", "abc"])
def test_a_bad_length_unit_in_a_link_is_named_with_its_range(text):
    ex = Explorer()
    said = ex.permalink.apply_query(f"scene=7c&units=SI&L={text}")
    assert said == [f"L (length_unit) must be a number in [1e-06, 1000]; got {text!r}"]
    assert ex.alert.visible and ex.state.length_unit == 0.01


@pytest.mark.parametrize("value", [0.0, -5.0, 2e6])
def test_a_bad_length_unit_typed_in_its_box_is_named_with_its_range(value):
    state = ExplorerState(units="SI")
    reason = refusal_si(state, "L", value, "length unit L", 1e-3)
    assert reason == (f"length unit L must lie in [0.001, 1e+06] mm; got {value:g} mm")
    with pytest.raises(ValueError, match=r"length unit L must lie in \[0.001, 1e\+06\] mm"):
        state.from_physical(L=value)


def test_a_length_out_of_range_in_mm_names_its_range_in_mm_with_L():
    state = ExplorerState(units="SI")
    with pytest.raises(ValueError, match=r"clearance x̄ must lie in \[-100, 100\] mm with "
                                         r"L = 10 mm; got 500 mm"):
        state.from_physical(clearance=500.0)


def test_in_si_the_length_boxes_show_millimetres_and_commit_in_units_of_L():
    ex = Explorer()
    ex.permalink.apply_query("scene=7c")
    ex.controls.commit({"units": "SI"})
    sliders = ex.controls.sliders
    for name in LENGTHS:
        box = sliders[f"{name}_si"]
        assert box.label.endswith("(mm)"), box.label
        factor = si_units(0.5, 200.0, 0.01)[name][2]
        assert factor == 0.01 * MM_PER_M
        assert box.value == pytest.approx(getattr(ex.state, name) * factor)
    assert sliders["clearance_si"].visible and not sliders["clearance"].visible
    assert sliders["length_unit_si"].value == 10.0
    sliders["clearance_si"].input.value = "4"
    assert ex.state.clearance == pytest.approx(0.4, rel=ROUND_TRIP_RTOL)
    sliders["length_unit_si"].input.value = "5"
    assert ex.state.length_unit == 0.005 and ex.state.clearance == pytest.approx(0.4)
    assert sliders["clearance_si"].value == pytest.approx(2.0)
    # The slider's range is the dimensionless one's, 1e3 L times: both its ends follow L
    # (the lower end stayed where a larger L had put it).
    soft = ExplorerState.param.clearance.softbounds
    slider = sliders["clearance_si"].slider
    assert (slider.start, slider.end) == pytest.approx((soft[0] * 5.0, soft[1] * 5.0))
    sliders["length_unit_si"].input.value = "1000"
    assert (slider.start, slider.end) == pytest.approx((soft[0] * 1e3, soft[1] * 1e3))
    sliders["length_unit_si"].input.value = "10"
    assert (slider.start, slider.end) == pytest.approx((soft[0] * 10.0, soft[1] * 10.0))
    ex.controls.commit({"units": "dimensionless"})
    assert sliders["clearance"].visible and not sliders["clearance_si"].visible


def test_a_tap_in_si_reads_the_axes_in_millimetres():
    """The phase portrait's and the regime map's axes are in mm in SI: a tap at x = 2 mm
    with L = 10 mm is x0 = 0.2 units of L (it was taken as 2, a start beyond the stop),
    and the tapped point is drawn where it was tapped."""
    from bokeh.events import Tap

    ex = Explorer()
    ex.permalink.apply_query("scene=5a&units=SI")
    assert ex.state.length_unit == 1.0  # an SI link without L (its lengths in metres)
    ex.state.length_unit = 0.01
    scales = ex.state.scales()
    ex.host.phase_tapped(Tap(ex.plots.figures["phase"], x=2.0, y=0.01))
    assert ex.state.x0 == 0.2 and ex.state.v0 == round(0.01 / scales.velocity, 4)
    assert ex.plots.sources["start"].data["x"] == [pytest.approx(2.0)]
    ex.host.map_tapped(Tap(ex.plots.figures["map"], x=0.01, y=2.5))
    assert ex.state.clearance == 0.25
    assert ex.plots.sources["here"].data["x"] == [pytest.approx(2.5)]
