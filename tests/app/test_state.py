"""State -> core parameters, units and permalink keys (no browser)."""

from __future__ import annotations

import math

import pytest

from app.state import SOLVE_PARAMS, URL_KEYS, ExplorerState, core_inputs, scene_values
from core import HystereticStop, Oscillator, RigidStop


def test_rigid_state_maps_to_core_inputs():
    state = ExplorerState(belt_speed=0.15, clearance=0.27, restitution=0.6, mu_s=0.4,
                          mu_k=0.25, u_s=2.0, x0=-0.1, v0=0.05, t_end=33.0,
                          stop_type="rigid")
    osc, stop, x0, v0, t_end = state.core_inputs()
    assert osc == Oscillator(mu_s=0.4, mu_k=0.25, belt_speed=0.15, u_s=2.0)
    assert (osc.a, osc.b) == pytest.approx((0.5, 0.8))
    assert stop == RigidStop(clearance=0.27, restitution=0.6)
    assert (x0, v0, t_end) == (-0.1, 0.05, 33.0)


def test_hysteretic_and_no_stop():
    state = ExplorerState(stop_type="hysteretic", clearance=0.2, k_c0=100.0, k_e0=25.0,
                          limit_overlap=0.03, beta_c=4.0, beta_e=6.0)
    stop = state.core_inputs()[1]
    assert stop == HystereticStop(clearance=0.2, k_c0=100.0, k_e0=25.0, limit_overlap=0.03,
                                  beta_c=4.0, beta_e=6.0)
    assert stop.equivalent_restitution == pytest.approx(0.5)
    state.stop_type = "none"
    assert state.core_inputs()[1] is None


@pytest.mark.parametrize(
    ("override", "word"),
    [({"mu_k": 0.5, "mu_s": 0.3}, "mu_k"), ({"clearance": -0.1, "x0": 0.0}, "ahead"),
     ({"k_e0": 500.0, "k_c0": 100.0, "stop_type": "hysteretic"}, "k_e0"),
     ({"t_end": 0.0}, "t_end")],
)
def test_invalid_values_raise_with_the_parameter_named(override, word):
    values = {**ExplorerState().values(), **override}
    with pytest.raises(ValueError, match=word):
        core_inputs(values)


def test_si_conversion_both_ways():
    # A length unit of 1 m: the state's lengths read as metres.
    state = ExplorerState(units="SI", mass=2.0, stiffness=200.0, length_unit=1.0)
    state.set_physical(normal_force=60.0, belt_speed=1.0)
    omega = math.sqrt(100.0)
    assert state.u_s == pytest.approx(60.0 / 200.0)
    assert state.belt_speed == pytest.approx(1.0 / omega)
    phys = state.physical()
    assert phys["normal_force"] == pytest.approx(60.0)
    assert phys["belt_speed"] == pytest.approx(1.0)
    # A new stiffness keeps the physical F_N and v_dr, so u_s and v change.
    state.set_physical(k=800.0)
    assert state.u_s == pytest.approx(60.0 / 800.0)
    assert state.belt_speed == pytest.approx(1.0 / math.sqrt(400.0))
    sc = state.scales()
    assert sc.si and sc.time == pytest.approx(1 / 20.0) and sc.velocity == pytest.approx(20.0)
    assert sc.force == 800.0


def test_si_start_velocity_and_horizon_both_ways():
    state = ExplorerState(mass=1.0, stiffness=100.0, v0=0.05, t_end=60.0,
                          length_unit=1.0)  # omega = 10
    phys = state.physical()
    assert phys["v0"] == pytest.approx(0.5) and phys["t_end"] == pytest.approx(6.0)
    state.set_physical(v0=-1.0, t_end=2.5)
    assert state.v0 == pytest.approx(-0.1) and state.t_end == pytest.approx(25.0)
    # A new mass keeps the seconds and metres per second (as it keeps F_N and v_dr).
    state.set_physical(m=4.0)  # omega = 5
    assert state.t_end == pytest.approx(12.5) and state.v0 == pytest.approx(-0.2)
    assert state.physical()["t_end"] == pytest.approx(2.5)
    # The bound in the seconds the box shows (it said "t_end = 5e+06 (from the SI values)
    # must lie in [0.1, 5000]", the dimensionless numbers beside a box in seconds).
    with pytest.raises(ValueError, match=r"t_end must lie in \[0.02, 1000\] s with m = 4 kg, "
                       r"k = 100 N/m; got 1e\+06 s"):
        state.set_physical(t_end=1e6)
    with pytest.raises(ValueError, match="unknown SI value"):
        state.from_physical(mu_s=1.0)


def test_si_stop_stiffnesses_both_ways():
    state = ExplorerState(stiffness=100.0, k_c0=400.0, k_e0=36.0)
    phys = state.physical()
    assert (phys["k_c0"], phys["k_e0"]) == (40_000.0, 3_600.0)
    state.set_physical(k_c0=50_000.0)
    assert state.k_c0 == 500.0 and state.k_e0 == 36.0
    # A new k keeps the stop's stiffnesses in N/m (as it keeps F_N and v_dr).
    state.set_physical(k=200.0)
    assert (state.k_c0, state.k_e0) == (250.0, 18.0)
    assert state.physical()["k_c0"] == pytest.approx(50_000.0)
    with pytest.raises(ValueError, match=r"k_c0 must lie in \[0.2, 2e\+08\] N/m .* got 1e\+12"):
        state.set_physical(k_c0=1e12)


def test_set_physical_rejects_bad_si_input():
    state = ExplorerState()
    with pytest.raises(ValueError, match="m must lie"):
        state.set_physical(m=-1.0)


def test_every_url_key_is_a_parameter_and_unique():
    assert set(URL_KEYS) <= set(ExplorerState.param)
    assert len(set(URL_KEYS.values())) == len(URL_KEYS)
    assert set(SOLVE_PARAMS) <= set(URL_KEYS)


def test_load_scene_keeps_accuracy_and_method():
    state = ExplorerState(accuracy="precise", method="switch")
    state.load_scene("7b")
    assert state.scene == "7b"
    assert (state.accuracy, state.method) == ("precise", "switch")
    assert state.values() == scene_values("7b", accuracy="precise", method="switch")


def test_the_contact_law_reaches_the_deformable_stop():
    """The page's contact law is the core's ``HystereticStop.law``; the scenes use the
    paper's reading and a bad name is refused with the allowed ones."""
    values = scene_values("10")
    assert values["contact_law"] == "paper"
    assert core_inputs(values)[1].law == "paper"
    assert core_inputs({**values, "contact_law": "passive"})[1].law == "passive"
    assert URL_KEYS["contact_law"] == "law"
    with pytest.raises(ValueError, match="passive"):
        ExplorerState(contact_law="plastic")


def test_the_si_default_is_a_bench_spring_and_the_page_says_so():
    """The SI default was m = 1 kg, k = 100 N/m; it is a bench rig's 0.5 kg on 200 N/m
    with a length unit of 10 mm (it was 1 m: the scenes' u_s = 1 pressed the block with
    200 N), and the units' tooltip states it with the numbers it gives a scene."""
    from app.controls import si_default_tip
    from app.scenes import SCENES

    state = ExplorerState(units="SI")
    assert (state.mass, state.stiffness, state.length_unit) == (0.5, 200.0, 0.01)
    omega = math.sqrt(200.0 / 0.5)
    assert state.omega == pytest.approx(omega, rel=1e-15)
    tip = si_default_tip()
    assert "m = 0.5 kg, k = 200 N/m and a length unit L = 10 mm" in tip
    assert "F_N = k L uₛ = 2 N" in tip and "static deflection of 10 mm" in tip
    assert f"ω = {omega:.3g} rad/s" in tip and f"{2 * math.pi / omega:.2g} s" in tip
    # Every scene maps to SI numbers of one bench: seconds to minutes of run, belts below
    # 1 m/s, a normal force of a few newtons (k L u_s), clearances of millimetres.
    for key in SCENES:
        values = scene_values(key)
        phys = ExplorerState(**values, units="SI").physical()
        assert 0.1 < phys["t_end"] < 300.0 and 0.0 < phys["belt_speed"] < 1.0, key
        assert phys["normal_force"] == pytest.approx(200.0 * 0.01 * values["u_s"])
        assert 0.1 <= phys["normal_force"] <= 20.0, key
        assert abs(phys["clearance"]) < 50.0, key  # mm
