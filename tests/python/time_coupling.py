"""Time of one coupling step from Python (compare: `cargo run -p aqua-sim --example
coupling_step`, the same 200 steps of the 160-segment chain from Rust)."""

import math
import pathlib
import time

import aqua

ROOT = pathlib.Path(__file__).resolve().parents[2]
text = (ROOT / "examples" / "mooring-chain.toml").read_text().replace(
    "segments = 80", "segments = 160")
path = ROOT / "target" / "chain160.toml"
path.parent.mkdir(exist_ok=True)
path.write_text(text)
sim = aqua.Coupling(str(path))
sim.init()
dt, n, w = 0.1, 200, 2 * math.pi / 10.0


def ramp(t, tr=10.0):
    if t >= tr:
        return 1.0, 0.0
    s = t / tr
    return s * s * s * (10 + s * (-15 + 6 * s)), 30 * s * s * (1 - s) * (1 - s) / tr


t0 = time.perf_counter()
for k in range(1, n + 1):
    t1 = k * dt
    r, dr = ramp(t1)
    d = r * 1.5 * math.sin(w * t1)
    v = dr * 1.5 * math.sin(w * t1) + r * 1.5 * w * math.cos(w * t1)
    f = sim.step(sim.time, dt, {"chain/fairlead": {"position": [100.0 + d, 0.0, -5.0],
                                                    "velocity": [v, 0.0, 0.0]}})
per_step = (time.perf_counter() - t0) / n
print(f"python: {n} coupling steps of a 160-segment chain: {1e3 * per_step:.3f} ms per step "
      f"(last force {f['chain/fairlead'][0]} N)")
sim.close()
