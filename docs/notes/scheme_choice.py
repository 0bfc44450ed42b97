#!/usr/bin/env python3
"""Runs bundled examples with several dynamic settings and tabulates the differences.

Used for docs/notes/scheme-choice.md and docs/theory/fem.md#choice-of-the-default-scheme:

    python3 docs/notes/scheme_choice.py --aqua target/release/aqua --out /tmp/scheme-runs \
        moored-cage farm mooring-chain

For each example it runs (unless DIR/run.json exists already) the settings of SETTINGS:
the midpoint rule and HHT-α at the example's dt and at dt/4, plus any `--extra NAME:KEY=V,...`.
A row gives the dynamics wall, steps, halvings, Newton iterations per step, the warnings'
codes, and for every extremes column of a line group's largest tension (`Tmax_...`) or an
end load (`..._anchor_reaction`, `..._fairlead_reaction`, the total support reaction `R`) its
maximum in kN over every accepted step, with in brackets its difference in per cent from the
same scheme at dt/4 (`--ref LABEL` to choose another) and from the other scheme at dt/4.
"""

import argparse
import json
import os
import subprocess
import sys
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def example_dynamic(name):
    with open(os.path.join(ROOT, "examples", name + ".toml"), "rb") as f:
        scene = tomllib.load(f)
    return scene.get("analysis", {}).get("dynamic", {})


def settings(name, extra):
    """LABEL -> list of `--set` strings. `mid` keeps the file's θ (if any), `hht` resets it."""
    dyn = example_dynamic(name)
    dt = dyn.get("dt", 0.1)
    no_theta = ["theta=0.5"] if "theta" in dyn else []
    out = {}
    for scheme, sets in [("mid", ["scheme=midpoint"]), ("hht", ["scheme=hht"] + no_theta)]:
        out[f"{scheme}"] = sets + [f"dt={dt}"]
        out[f"{scheme}/4"] = sets + [f"dt={dt / 4}"]
    for spec in extra:
        label, _, keys = spec.partition(":")
        out[label] = [k for k in keys.split(",") if k]
    return out


def run(aqua, name, label, sets, out_dir, extra_sets):
    d = os.path.join(out_dir, name, label.replace("/", "_q"))
    if not os.path.exists(os.path.join(d, "run.json")):
        dyn = example_dynamic(name)
        interval = dyn.get("output_interval", max(dyn.get("dt", 0.1), dyn.get("t_end", 10.0) / 200))
        # No ParaView series but the first state: a whole multiple of the output interval.
        cmd = [aqua, "run", os.path.join(ROOT, "examples", name + ".toml"), "--out", d, "--quiet",
               "--set", f"paraview_interval={interval * 100000}"]
        for s in sets + extra_sets:
            cmd += ["--set", s]
        print("running", " ".join(cmd), file=sys.stderr, flush=True)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "stderr.txt"), "w") as err:
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=err)
    try:
        with open(os.path.join(d, "run.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def warning_tag(text):
    """A short name for a warning of run.json's `diagnostics` (they are "warning: ..." texts)."""
    for needle, tag in [("at this time step are uncertain", "time-step"),
                        ("extreme_tolerance", "extremes-unresolved"),
                        ("energy guard", "energy-guard")]:
        if needle in text:
            return tag
    return text[9:40]


def loads(run_json):
    ex = run_json.get("extremes") or {}
    return {
        c: v["max"]
        for c, v in ex.items()
        if c == "R" or c.startswith("Tmax_") or c.endswith(("_anchor_reaction", "_fairlead_reaction"))
        if isinstance(v, dict) and v.get("max") is not None
    }


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--aqua", default=os.path.join(ROOT, "target/release/aqua"))
    p.add_argument("--out", default="/tmp/scheme-runs")
    p.add_argument("--extra", action="append", default=[], help="LABEL:KEY=V,KEY=V")
    p.add_argument("--set", action="append", default=[], help="a --set for every run")
    p.add_argument("--ref", default=None, help="label of the reference (default: scheme at dt/4)")
    p.add_argument("--only", default=None, help="comma-separated labels to run")
    p.add_argument("examples", nargs="+")
    a = p.parse_args()
    for name in a.examples:
        table = settings(name, a.extra)
        if a.only:
            table = {k: v for k, v in table.items() if k in a.only.split(",")}
        runs = {k: run(a.aqua, name, k, v, a.out, a.set) for k, v in table.items()}
        print(f"\n### {name}\n")
        cols = sorted({c for r in runs.values() if r for c in loads(r)})
        print("| run | status | wall s | steps | halvings | it/step | ε_T % | warnings | "
              + " | ".join(cols) + " |")
        print("|" + "---|" * (8 + len(cols)))
        for label, r in runs.items():
            if r is None:
                print(f"| {label} | no run.json |")
                continue
            scheme = label.split("/")[0].split("+")[0]
            ref = runs.get(a.ref or (scheme + "/4"))
            other = runs.get({"mid": "hht/4", "hht": "mid/4"}.get(scheme, ""))
            sc = r.get("step_control") or {}
            steps = r.get("steps") or 0
            it = (r.get("newton_iterations") or 0) / steps if steps else 0
            warns = ",".join(sorted({warning_tag(d) for d in r.get("diagnostics", [])
                                     if str(d).startswith("warning")})) or "—"
            eps = (r.get("peak_tension_resolution") or {}).get("error", 0.0) * 100
            cells = []
            mine = loads(r)
            theirs = loads(ref) if ref and ref is not r else {}
            others = loads(other) if other else {}

            def delta(v, refs, c):
                return f"{100 * (v / refs[c] - 1):+.1f}" if refs.get(c) else "·"

            for c in cols:
                v = mine.get(c)
                if v is None:
                    cells.append("—")
                else:
                    cells.append(f"{v / 1e3:.2f} ({delta(v, theirs, c)}, {delta(v, others, c)})")
            print(f"| {label} | {r.get('status')} | {r.get('dynamic_wall_time_s', 0):.1f} | {steps} "
                  f"| {sc.get('halvings', 0)} | {it:.2f} | {eps:.2f} | {warns} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
