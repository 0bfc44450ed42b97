"""A feed barge moored by three chains, coupled to aqua (docs/guide/coupling.md).

The barge is this script's own model: a rigid body in the horizontal plane (surge, sway, yaw)
with its mass and added mass, linear hull damping, and a wind and current force that rises to
60 kN along x. aqua integrates the chains (barge-spread.toml, its own step 0.05 s) and returns
the force and moment they exert on the barge at every coupling step (0.2 s here). A step that
fails is retried in halves; the state is saved before a squall and restored to try it again.

    python examples/coupling/barge.py [duration_s]
"""

import math
import pathlib
import sys

import numpy as np

import aqua

HERE = pathlib.Path(__file__).resolve().parent
MASS = 1.2e6  # barge mass with surge/sway added mass [kg]
YAW_INERTIA = 8.0e7  # with added inertia [kg m²]
DAMPING = np.array([4.0e4, 4.0e4, 4.0e6])  # linear hull damping [N s/m, N s/m, N m s]
WIND = 6.0e4  # steady wind and current force on the barge [N], along x
RAMP = 30.0  # its rise time [s]
ORIGIN = [0.0, 0.0, -2.0]  # the barge's reference point as built (the fairleads' centre)


def environment(t, squall=0.0):
    """The wind and current force [Fx, Fy, Mz] on the barge at time t."""
    ramp = min(t / RAMP, 1.0)
    ramp = ramp * ramp * (3.0 - 2.0 * ramp)
    return np.array([WIND * ramp + squall, 0.2 * squall, 0.0])


def advance(sim, t, dt, q, u, squall=0.0):
    """One coupling step of the barge (semi-implicit Euler) from t to t + dt; halves the step
    and tries again when aqua's step fails. Returns t, q, u and the last forces."""
    try:
        f_moor = sim_force(sim, t, dt, q, u, squall)
    except aqua.SolveError:
        # aqua stayed at t: take the step in two halves.
        t, q, u, _ = advance(sim, t, dt / 2, q, u, squall)
        return advance(sim, t, dt / 2, q, u, squall)
    return t + dt, *integrate(t, dt, q, u, f_moor, squall)


def sim_force(sim, t, dt, q, u, squall):
    # Predict the barge at t + dt from its velocity, give aqua that pose, get the lines' load.
    q1, u1 = q + dt * u, u
    pose = [q1[0] + ORIGIN[0], q1[1] + ORIGIN[1], ORIGIN[2], 0.0, 0.0, q1[2]]
    vel = [u1[0], u1[1], 0.0, 0.0, 0.0, u1[2]]
    f = sim.step(t, dt, bodies={"barge": {"pose": pose, "velocity": vel}})
    return f


def integrate(t, dt, q, u, f, squall):
    w = f["barge"]
    load = np.array([w[0], w[1], w[5]]) + environment(t + dt, squall) - DAMPING * u
    acc = load / np.array([MASS, MASS, YAW_INERTIA])
    u = u + dt * acc
    q = q + dt * u
    return q, u, f


def main(duration=120.0, dt=0.2):
    sim = aqua.Coupling(str(HERE / "barge-spread.toml"))
    sim.add_body("barge", ["l1/fairlead", "l2/fairlead", "l3/fairlead"], origin=ORIGIN)
    sim.init()
    q, u = np.zeros(3), np.zeros(3)  # surge, sway [m], yaw [rad] and their rates
    t, peak, f = 0.0, 0.0, None
    while t < duration - 1e-9:
        t, q, u, f = advance(sim, t, dt, q, u)
        peak = max(peak, sim.tensions().max())
    print(f"t = {t:.1f} s: barge at x = {q[0]:.3f} m, y = {q[1]:.3f} m, yaw = {math.degrees(q[2]):.3f}°")
    print(f"lines on the barge: Fx = {f['barge'][0] / 1e3:.1f} kN "
          f"(wind and current {environment(t)[0] / 1e3:.1f} kN), largest tension {peak / 1e3:.1f} kN")
    # What a 200 kN squall of 10 s would do, tried from a saved state and then undone.
    state = sim.save()
    qs, us, ts, squall_peak = q.copy(), u.copy(), t, 0.0
    while ts < t + 10.0 - 1e-9:
        ts, qs, us, _ = advance(sim, ts, dt, qs, us, squall=2.0e5)
        squall_peak = max(squall_peak, sim.tensions().max())
    print(f"a 10 s squall of 200 kN: barge to x = {qs[0]:.2f} m, largest tension "
          f"{squall_peak / 1e3:.1f} kN")
    sim.restore(state)
    assert math.isclose(sim.time, t, abs_tol=1e-9)
    sim.close()
    return q, f, peak, squall_peak


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 120.0)
