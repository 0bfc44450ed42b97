"""aqua.Coupling as a vessel code uses it (docs/guide/coupling.md): a rigid body carrying
three fairleads against the same motion run by the CLI, save/restore, a failed step retried,
and the structure read mid-run."""

import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import aqua

from test_aqua import aqua_cli, read_summary, surge

ROOT = pathlib.Path(__file__).resolve().parents[2]
POINTS = ["l1/fairlead", "l2/fairlead", "l3/fairlead"]
# The body's surge and heave: amplitudes [m], one period and ramp for both.
SURGE, HEAVE = 1.5, 0.2


def spread(tmp_path, motion, dt=0.1, t_end=4.0, extra=""):
    """Three 62 m chains 120° apart, fairleads 10 m from the body centre at z = −5 m."""
    text = (f"[sea]\ndepth = 40.0\n[analysis]\nkind = \"static+dynamic\"\n"
            f"[analysis.dynamic]\ndt = {dt}\nt_end = {t_end}\noutput_interval = {dt}\n{extra}\n")
    for n, deg in enumerate([180.0, 60.0, -60.0], start=1):
        c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        text += (f"[[line]]\nname = \"l{n}\"\nanchor = [{60 * c}, {60 * s}, -40.0]\n"
                 f"fairlead = [{10 * c}, {10 * s}, -5.0]\nlength = 62.0\nsegments = 10\n"
                 "diameter = 0.1354\nhydro_diameter = 0.076\nmass_per_length = 113.0\n"
                 "ea = 5.4e8\naxial_damping = 2.0e5\nmorison = \"const\"\ncn = 2.4\n"
                 "ct = 1.15\nadded_mass = 1.0\n"
                 f"[[prescribed]]\nnodes = \"l{n}/fairlead\"\n{motion}\n")
    p = tmp_path / "spread.toml"
    p.write_text(text)
    return p


def body_target(t):
    """The body's pose, velocity and acceleration at t: the scene's sine motion, written out."""
    d, v, a = surge(t, amplitude=1.0, period=10.0, ramp_time=5.0)
    k = [SURGE, 0.0, HEAVE]
    return {"pose": [k[0] * d, 0.0, -5.0 + k[2] * d, 0.0, 0.0, 0.0],
            "velocity": [k[0] * v, 0.0, k[2] * v, 0.0, 0.0, 0.0],
            "acceleration": [k[0] * a, 0.0, k[2] * a, 0.0, 0.0, 0.0]}


def test_a_coupled_body_gives_the_forces_of_the_same_motion_run_by_the_cli(tmp_path):
    dt, t_end = 0.1, 3.0
    sine = (f"motion = \"sine\"\namplitude = [{SURGE}, 0.0, {HEAVE}]\nperiod = 10.0\n"
            "ramp_time = 5.0")
    out = tmp_path / "cli"
    r = aqua_cli("run", str(spread(tmp_path, sine, dt, t_end)), "--out", str(out), "--quiet")
    assert r.returncode == 0, r.stderr
    cli = read_summary(out)
    assert np.all(cli["dt"][1:] == pytest.approx(dt, rel=1e-9))

    sim = aqua.Coupling(str(spread(tmp_path, "motion = \"coupled\"", dt, t_end)),
                        out=str(tmp_path / "coupled"))
    sim.add_body("barge", POINTS, origin=[0.0, 0.0, -5.0])
    assert sim.bodies == ["barge"]
    f = sim.init()
    history = {p: [np.linalg.norm(f[p][0])] for p in POINTS}
    for k in range(1, round(t_end / dt) + 1):
        f = sim.step(sim.time, dt, bodies={"barge": body_target(k * dt)})
        for p in POINTS:
            history[p].append(np.linalg.norm(f[p][0]))
        # The body's force is the sum of its fairleads' (a pure translation: no lever arm
        # changes, the moment is Σ r × f about the moved reference point).
        np.testing.assert_allclose(f["barge"][:3], sum(f[p][0] for p in POINTS), rtol=1e-12)
    sim.close()
    coupled = read_summary(tmp_path / "coupled")
    for n, p in enumerate(POINTS, start=1):
        np.testing.assert_allclose(history[p], cli[f"l{n}_fairlead_reaction"], rtol=1e-9)
        # The coupled run's own summary.csv holds the same history as aqua run's.
        np.testing.assert_allclose(coupled[f"l{n}_fairlead_reaction"],
                                   cli[f"l{n}_fairlead_reaction"], rtol=1e-9)
    assert (tmp_path / "coupled" / "extremes.csv").exists()
    assert len(list((tmp_path / "coupled").glob("*.pvd"))) == 1


def test_save_restore_and_a_failed_step_retried(tmp_path):
    sim = aqua.Coupling(str(spread(tmp_path, "motion = \"coupled\"", extra="max_strain = 0.05")))
    sim.add_body("barge", POINTS, origin=[0.0, 0.0, -5.0])
    sim.init()
    dt = 0.1
    for k in range(1, 11):
        sim.step(sim.time, dt, bodies={"barge": body_target(k * dt)})
    state = sim.save()
    assert state.time == pytest.approx(1.0)

    def ten_more():
        for k in range(11, 21):
            f = sim.step(sim.time, dt, bodies={"barge": body_target(k * dt)})
        return f, sim.tensions(), sim.positions()

    first = ten_more()
    sim.restore(state)
    assert sim.time == state.time
    again = ten_more()
    for p in POINTS + ["barge"]:
        assert np.array_equal(first[0][p], again[0][p])
    assert np.array_equal(first[1], again[1]) and np.array_equal(first[2], again[2])

    # 30 m in one step stretches a chain past the strain guard: the step fails, the coupling
    # stays where it was, and the smaller step goes on.
    t = sim.time
    with pytest.raises(aqua.SolveError) as e:
        sim.step(t, dt, {"l1/fairlead": [30.0, 0.0, -5.0]})
    assert e.value.reason == "strain … beyond max_strain …"
    assert t <= e.value.time < t + dt
    assert sim.time == t
    sim.step(t, dt / 2, bodies={"barge": body_target(t + dt / 2)})
    assert sim.time == pytest.approx(t + dt / 2)

    # The structure mid-run: one tension per element, named by group and node pair.
    tensions, elements, groups = sim.tensions(), sim.elements, sim.groups
    assert tensions.shape == (30,) and elements.shape == (30, 2)
    assert sorted(groups) == ["l1/l1", "l2/l2", "l3/l3"]
    assert np.all(tensions >= 0.0)
    sim.close()


def test_the_barge_example_reaches_the_force_balance_of_its_wind(tmp_path):
    # examples/coupling/barge.py, the worked example of docs/guide/coupling.md: after the
    # barge's surge has died down, the chains hold the 60 kN of wind and current.
    import importlib.util
    spec = importlib.util.spec_from_file_location("barge", ROOT / "examples/coupling/barge.py")
    barge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(barge)
    q, f, peak, squall_peak = barge.main(duration=400.0)
    assert abs(f["barge"][0] + barge.WIND) < 0.01 * barge.WIND
    # Downwind, not turned, and the squall loads the lines harder than the steady wind.
    assert q[0] > 0.0 and abs(q[1]) < 1e-6 and abs(q[2]) < 1e-6
    assert squall_peak > peak
