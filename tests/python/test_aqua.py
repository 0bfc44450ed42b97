"""The Python module `aqua` against the `aqua` binary: the same scene gives the same numbers,
and the same mistakes give the same messages.

The binary is $AQUA_BIN (CI sets it to the one `cargo test` built), else `cargo run`.
"""

import csv
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import aqua

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHAIN = ROOT / "examples" / "mooring-chain.toml"


def aqua_cli(*args):
    exe = os.environ.get("AQUA_BIN")
    cmd = [exe] if exe else ["cargo", "run", "--quiet", "-p", "aqua-cli", "--"]
    return subprocess.run(cmd + list(args), cwd=ROOT, capture_output=True, text=True)


def read_summary(out):
    with open(out / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def chain_scene(tmp_path, t_end, output_interval):
    # The example's chain (the midpoint rule) at dt 0.1 s.
    text = CHAIN.read_text()
    assert "dt = 0.025\n" in text
    text = text.replace("dt = 0.025\n", "dt = 0.1\n")
    text = text.replace("t_end = 60.0", f"t_end = {t_end}")
    text = text.replace("output_interval = 0.5", f"output_interval = {output_interval}")
    p = tmp_path / "chain.toml"
    p.write_text(text)
    return p


def test_chain_example_static_fairlead_tension_matches_the_cli(tmp_path):
    out = tmp_path / "cli"
    r = aqua_cli("run", str(CHAIN), "--out", str(out), "--quiet")
    assert r.returncode == 0, r.stderr
    cli = read_summary(out)

    scene = aqua.Scene.load(str(CHAIN))
    assert scene.name == "mooring-chain"
    assert scene.check() == []
    res = scene.run(out=str(tmp_path / "py"))
    assert res.status == "completed"
    assert res.columns == list(cli.keys())
    n = len(cli["t"])
    assert len(res) == n and res.times[-1] == pytest.approx(60.0)
    assert res.positions.shape == (n, 81, 3)
    assert res.tensions.shape == (n, 80)
    for col in ("chain_fairlead_reaction", "chain_fairlead_element_tension", "Rz"):
        py, ref = res.summary[col][0], cli[col][0]
        assert abs(py - ref) <= 1e-12 * abs(ref), (col, py, ref)
    # The whole history too (same code, same order of operations).
    np.testing.assert_allclose(res.summary["chain_fairlead_reaction"],
                               cli["chain_fairlead_reaction"], rtol=1e-12)
    # The Python run wrote the CLI's files.
    assert (tmp_path / "py" / "summary.csv").read_text() == (out / "summary.csv").read_text()
    # Independent check of the static state: the fairlead reaction balances the chain's
    # tension at the fairlead element (|R| >= T_end, equal within the element's own weight).
    w_elem = (113.0 - 1025.0 * math.pi / 4 * 0.1354**2) * 9.80665 * 120.0 / 80
    assert abs(cli["chain_fairlead_reaction"][0] - cli["chain_fairlead_element_tension"][0]) < w_elem


def files_under(d):
    return sorted(str(p.relative_to(d)) for p in d.rglob("*"))


def test_a_python_run_writes_the_files_of_the_cli(tmp_path):
    # A dynamic run in waves: every output file, the wave component table included.
    text = (ROOT / "examples" / "moored-cage.toml").read_text()
    assert "t_end = 60.0" in text
    scene = tmp_path / "moored-cage.toml"
    scene.write_text(text.replace("t_end = 60.0", "t_end = 0.4"))
    cli, py = tmp_path / "cli", tmp_path / "py"
    r = aqua_cli("run", str(scene), "--out", str(cli), "--quiet")
    assert r.returncode == 0, r.stderr
    res = aqua.Scene.load(str(scene)).run(out=str(py))
    assert res.status == "completed"

    names = files_under(cli)
    for f in ("run.json", "summary.csv", "extremes.csv", "wave_components.csv",
              "open_in_paraview.py", "moored-cage.pvd"):
        assert f in names, f
    assert files_under(py) == names
    for f in ("summary.csv", "extremes.csv", "wave_components.csv"):
        assert (py / f).read_text() == (cli / f).read_text(), f
    a = json.loads((cli / "run.json").read_text())
    b = json.loads((py / "run.json").read_text())
    assert list(b) == list(a)
    for k in ("status", "output_steps", "paraview_steps", "steps", "final", "extremes",
              "resolved", "names", "diagnostics"):
        assert b[k] == a[k], k


def surge(t, amplitude=1.5, period=10.0, ramp_time=10.0):
    """The example's fairlead surge d = r(t)·A·sin(2πt/T), with the smooth start
    r = 10s³ − 15s⁴ + 6s⁵ (s = t/t_r), and its first two derivatives."""
    if ramp_time <= 0.0 or t >= ramp_time:
        r, dr, ddr = 1.0, 0.0, 0.0
    elif t <= 0.0:
        r, dr, ddr = 0.0, 0.0, 0.0
    else:
        s = t / ramp_time
        r = s * s * s * (10.0 + s * (-15.0 + 6.0 * s))
        dr = 30.0 * s * s * (1.0 - s) * (1.0 - s) / ramp_time
        ddr = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (ramp_time * ramp_time)
    w = 2.0 * math.pi / period
    sn, cs = math.sin(w * t + 0.0), math.cos(w * t + 0.0)
    g, dg, ddg = 0.0 + amplitude * sn, amplitude * w * cs, -amplitude * w * w * sn
    return r * g, dr * g + r * dg, ddr * g + 2.0 * dr * dg + r * ddg


def test_coupling_with_the_prescribed_surge_reproduces_the_cli_run(tmp_path):
    # 6 s at dt = 0.1 s with an output every step: the CLI evaluates the surge analytically,
    # the coupling gets it from Python at the end of each step. (Where the solver halves a
    # step, the coupling interpolates between the given states instead; the run below has
    # no halving, which the dt column confirms.)
    dt, t_end = 0.1, 6.0
    scene_path = chain_scene(tmp_path, t_end, dt)
    out = tmp_path / "cli"
    r = aqua_cli("run", str(scene_path), "--out", str(out), "--quiet")
    assert r.returncode == 0, r.stderr
    cli = read_summary(out)
    assert np.all(cli["dt"][1:] == pytest.approx(dt, rel=1e-9))

    sim = aqua.Coupling(aqua.Scene.load(str(scene_path)))
    assert sim.points == ["chain/fairlead"]
    f0 = sim.init()["chain/fairlead"]
    assert f0.shape == (1, 3)
    history = [np.linalg.norm(f0[0])]
    fairlead = np.array([100.0, 0.0, -5.0])
    n = round(t_end / dt)
    for k in range(1, n + 1):
        t1 = k * dt
        d, v, a = surge(t1)
        f = sim.step(sim.time, dt, {"chain/fairlead": {
            "position": fairlead + [d, 0.0, 0.0],
            "velocity": [v, 0.0, 0.0],
            "acceleration": [a, 0.0, 0.0],
        }})
        history.append(np.linalg.norm(f["chain/fairlead"][0]))
    assert sim.time == pytest.approx(t_end)
    # The force on the vessel pulls it towards the anchor and down.
    assert f["chain/fairlead"][0][0] < 0 and f["chain/fairlead"][0][2] < 0
    sim.close()
    np.testing.assert_allclose(history, cli["chain_fairlead_reaction"], rtol=1e-9, atol=0)
    with pytest.raises(aqua.AquaError, match="closed"):
        sim.step(t_end, dt, {})


def test_coupling_rejects_unknown_points_and_wrong_times(tmp_path):
    sim = aqua.Coupling(str(chain_scene(tmp_path, 1.0, 0.1)))
    with pytest.raises(aqua.AquaError, match="init"):
        sim.step(0.0, 0.1, {})
    sim.init()
    with pytest.raises(aqua.AquaError, match="chain/fairlead"):
        sim.step(0.0, 0.1, {"chain/anchor": [0.0, 0.0, -50.0]})
    with pytest.raises(aqua.AquaError, match="model is at t = 0"):
        sim.step(1.0, 0.1, {})
    sim.close()


@pytest.mark.parametrize("case,text", [
    ("alpha", "[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nalpha = 0.5\n"),
    ("key", "[sea]\ndepth = 50\ndepht = 3\n"),
    ("point", "[[point]]\nnodes = \"nowhere\"\nmass = 10\n"),
])
def test_an_invalid_scene_raises_with_the_cli_message(tmp_path, case, text):
    base = ("[[line]]\nanchor = [0, 0, -50]\nfairlead = [40, 0, -5]\nlength = 70\n"
            "segments = 10\ndiameter = 0.1\nmass_per_length = 50\nea = 1e8\n")
    p = tmp_path / f"{case}.toml"
    p.write_text(text if case == "key" else base + "\n" + text)
    r = aqua_cli("check", str(p))
    assert r.returncode == 2, r.stderr
    message = r.stderr.strip().removeprefix("error: ")
    assert str(p) in message
    with pytest.raises(aqua.AquaError) as e:
        aqua.Scene.load(str(p)).check()
    assert str(e.value).strip() == message


def test_a_bad_key_raises_input_error_as_the_cli_exits_with_2(tmp_path):
    p = tmp_path / "key.toml"
    p.write_text("[sea]\ndepth = 50\ndepht = 3\n")
    assert aqua_cli("check", str(p)).returncode == 2
    with pytest.raises(aqua.InputError, match="depht") as e:
        aqua.Scene.load(str(p))
    assert isinstance(e.value, aqua.AquaError) and not isinstance(e.value, aqua.SolveError)
    with pytest.raises(aqua.InputError, match="depht"):
        aqua.Scene.from_dict({"sea": {"depth": 50, "depht": 3}})


def test_a_static_solve_that_cannot_converge_raises_solve_error(tmp_path):
    # One Newton iteration for the whole load, no smaller increments: the chain's catenary is
    # not reached, a failed computation (the binary exits with 1, not 2).
    text = CHAIN.read_text().replace(
        'kind = "static+dynamic"',
        'kind = "static"\n\n[analysis.static]\nmax_iter = 1\nmin_load_step = 1.0',
    )
    p = tmp_path / "stuck.toml"
    p.write_text(text)
    r = aqua_cli("run", str(p), "--out", str(tmp_path / "cli"), "--quiet")
    assert r.returncode == 1, r.stderr
    assert "static equilibrium failed" in r.stderr
    with pytest.raises(aqua.SolveError, match="static equilibrium failed") as e:
        aqua.Scene.load(str(p)).run()
    assert isinstance(e.value, aqua.AquaError) and not isinstance(e.value, aqua.InputError)


def test_scene_from_dict_is_the_same_scene():
    tomllib = pytest.importorskip("tomllib")
    with open(CHAIN, "rb") as f:
        d = tomllib.load(f)
    d["analysis"] = {"kind": "static"}
    res = aqua.Scene.from_dict(d, str(CHAIN)).run()
    assert len(res) == 1 and res.summary["chain_fairlead_reaction"][0] > 7e4


def test_a_pipe_modelled_as_a_rod_gives_mesh_positions_and_its_stress(tmp_path):
    # A sagging HDPE pipe between two held ends: its bending group is a rod whose twist
    # carriers follow the mesh's nodes in the model; the results keep to the mesh's 11 nodes
    # and report the pipe's largest fibre stress as the binary does.
    text = (
        "[sea]\ndepth = 50.0\n\n[[line]]\nname = \"pipe\"\nanchor = [0.0, 0.0, -5.0]\n"
        "fairlead = [20.0, 0.0, -5.0]\nlength = 20.0\nsegments = 10\nshape = \"straight\"\n"
        "diameter = 0.25\nsdr = 17.0\nyoungs_modulus = 9.0e8\ndensity = 2000.0\n"
        "fixed = [\"anchor\", \"fairlead\"]\n\n[analysis]\nkind = \"static\"\n"
    )
    p = tmp_path / "pipe.toml"
    p.write_text(text)
    out = tmp_path / "cli"
    r = aqua_cli("run", str(p), "--out", str(out), "--quiet")
    assert r.returncode == 0, r.stderr
    cli = read_summary(out)
    col = "stress_max_pipe/pipe"
    assert col in cli and cli[col][0] > 0.0
    res = aqua.Scene.load(str(p)).run(out=str(tmp_path / "py"))
    assert res.positions.shape == (1, 11, 3)
    assert res.summary[col][0] == pytest.approx(cli[col][0], rel=1e-12)


def test_errors_say_where_and_why_to_a_program(tmp_path):
    # An input error names the file, key and value; a failed step its kind and time, so a
    # script or a sweep can act on the cause without reading the message.
    text = CHAIN.read_text().replace("t_end = 60.0", "t_end = 60.0\ntheta = 0.3")
    p = tmp_path / "theta.toml"
    p.write_text(text.replace('kind = "static+dynamic"', 'kind = "static+dynamic"'))
    with pytest.raises(aqua.InputError) as e:
        aqua.Scene.load(str(p)).run()
    assert e.value.key == "analysis.dynamic.theta"
    assert float(e.value.value) == 0.3 and e.value.file == str(p)
    with pytest.raises(aqua.InputError) as e:
        aqua.Scene.from_dict({"sea": {"depth": 50, "depht": 3}})
    assert hasattr(e.value, "key")
