#!/usr/bin/env python3
"""Independent check of aqua's VTK output (.vtu / .vtm / .pvd) with meshio.

Usage:
  check_vtk.py FILE [--expect EXPECT.json] [--points N] [--cells line=N,triangle=N,quad=N]
               [--point-arrays name:ncomp,...] [--cell-arrays name:ncomp,...] [--times t0,t1,...]

FILE is a .vtu (checked directly), a .vtm (a multiblock step of `aqua run`, or the geometry of
`aqua mesh --out`: every block .vtu it lists is read) or a .pvd (every listed file is checked, and the time values are compared with
--times). For a .vtm, "points" and "cells" are the sums over its blocks (points over the
`points` datasets, cells over `lines` and `panels`), "point_arrays" are checked in every block,
"line_arrays" {name: ncomp} in the `lines` blocks, and the field data `TimeValue` must equal
the .pvd time. Expectations given on the command line override those in the JSON
file, whose keys are: "points", "cells" {type: count}, "point_arrays" {name: ncomp},
"cell_arrays" {name: ncomp}, "times" [..].

Checks: exactly the expected cell types and counts, point count, connectivity in range, VTK_QUAD
node order (both triangles of each quad turn the same way, non-zero area), arrays present with
n x ncomp finite values, all point coordinates finite, .pvd time values and files on disk.
Exit status 0 when every check passes, 1 otherwise (failures are listed), 2 on usage errors.
"""
import argparse
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np


def parse_pairs(text, conv):
    out = {}
    if not text:
        return out
    for item in text.split(","):
        key, sep, val = item.partition("=" if "=" in item else ":")
        if not sep:
            raise SystemExit(f"check_vtk: cannot read `{item}` (expected name=value or name:value)")
        out[key.strip()] = conv(val)
    return out


def check_vtu(path, exp, fails):
    try:
        mesh = meshio.read(path)
    except Exception as e:  # noqa: BLE001 - report any reader failure
        fails.append(f"{path}: meshio cannot read it: {e}")
        return
    n = len(mesh.points)
    if not np.all(np.isfinite(mesh.points)):
        fails.append(f"{path}: non-finite point coordinates")
    if "points" in exp and n != exp["points"]:
        fails.append(f"{path}: {n} points, expected {exp['points']}")
    counts = {}
    for block in mesh.cells:
        data = np.asarray(block.data)
        # meshio 5.3 returns UInt64 connectivity as float64 (uint64/int64 promotion): accept it
        # only if every index is integral.
        if data.dtype.kind == "f":
            if not np.all(np.equal(np.mod(data, 1), 0)):
                fails.append(f"{path}: {block.type} connectivity has non-integer indices")
                continue
        data = data.astype(np.int64)
        counts[block.type] = counts.get(block.type, 0) + len(data)
        if len(data) and (data.min() < 0 or data.max() >= n):
            fails.append(f"{path}: {block.type} connectivity out of range [0, {n})")
        if block.type == "quad":
            p = mesh.points[data]
            n1 = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
            n2 = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])
            dots = np.einsum("ij,ij->i", n1, n2)
            bad = np.flatnonzero(dots <= 0.0)
            if len(bad):
                fails.append(f"{path}: {len(bad)} quads not in cyclic VTK_QUAD order (first: {bad[0]})")
    if "cells" in exp:
        want = {k: v for k, v in exp["cells"].items() if v}
        have = {k: v for k, v in counts.items() if v}
        if want != have:
            fails.append(f"{path}: cells {have}, expected {want}")
    ncells = sum(counts.values())
    for name, ncomp in exp.get("point_arrays", {}).items():
        if name not in mesh.point_data:
            fails.append(f"{path}: point array `{name}` missing (have {sorted(mesh.point_data)})")
            continue
        a = np.asarray(mesh.point_data[name])
        k = 1 if a.ndim == 1 else a.shape[1]
        if a.shape[0] != n or k != ncomp:
            fails.append(f"{path}: point array `{name}` has shape {a.shape}, expected ({n}, {ncomp})")
        if not np.all(np.isfinite(a)):
            fails.append(f"{path}: point array `{name}` has non-finite values")
    for name, ncomp in exp.get("cell_arrays", {}).items():
        if name not in mesh.cell_data:
            fails.append(f"{path}: cell array `{name}` missing (have {sorted(mesh.cell_data)})")
            continue
        blocks = [np.asarray(b) for b in mesh.cell_data[name]]
        a = np.concatenate([b.reshape(len(b), -1) for b in blocks]) if blocks else np.zeros((0, 1))
        if a.shape[0] != ncells or a.shape[1] != ncomp:
            fails.append(f"{path}: cell array `{name}` has shape {a.shape}, expected ({ncells}, {ncomp})")
        if not np.all(np.isfinite(a)):
            fails.append(f"{path}: cell array `{name}` has non-finite values")
    print(f"{path}: {n} points, cells {counts}, point arrays {sorted(mesh.point_data)}, "
          f"cell arrays {sorted(mesh.cell_data)}")


def check_vtm(path, exp, fails, t=None):
    """Every block .vtu of a multiblock step, read with meshio (as a user of meshio would)."""
    try:
        root = ET.parse(path).getroot()
    except Exception as e:  # noqa: BLE001
        fails.append(f"{path}: not readable XML: {e}")
        return
    base = os.path.dirname(path)
    npts = 0
    cells = {}
    nfiles = 0
    for block in root.findall("./vtkMultiBlockDataSet/Block"):
        for ds in block.findall("./DataSet"):
            f = os.path.join(base, ds.get("file"))
            kind = ds.get("name")
            where = f"{path}: block {block.get('name')}/{kind}"
            try:
                mesh = meshio.read(f)
            # meshio 5.3 calls exit() on some files it cannot read (a String data array)
            except (Exception, SystemExit) as e:  # noqa: BLE001 - report any reader failure
                fails.append(f"{where}: meshio cannot read {f}: {e}")
                continue
            nfiles += 1
            n = len(mesh.points)
            if not np.all(np.isfinite(mesh.points)):
                fails.append(f"{where}: non-finite point coordinates")
            if kind == "points":
                npts += n
            else:
                for cb in mesh.cells:
                    cells[cb.type] = cells.get(cb.type, 0) + len(cb.data)
            want = dict(exp.get("point_arrays", {}))
            cwant = exp.get("line_arrays", {}) if kind == "lines" else {}
            for name, ncomp in list(want.items()) + list(cwant.items()):
                data = mesh.point_data.get(name) if name in want else None
                if name in cwant:
                    blocks = mesh.cell_data.get(name)
                    data = np.concatenate([np.asarray(b) for b in blocks]) if blocks else None
                if data is None:
                    fails.append(f"{where}: array `{name}` missing")
                    continue
                a = np.asarray(data)
                k = 1 if a.ndim == 1 else a.shape[1]
                if k != ncomp or not np.all(np.isfinite(a)):
                    fails.append(f"{where}: array `{name}` has shape {a.shape} (expected "
                                 f"{ncomp} components) or non-finite values")
            if t is not None:
                tv = mesh.field_data.get("TimeValue")
                if tv is None or not math.isclose(float(np.ravel(tv)[0]), t, rel_tol=1e-12,
                                                  abs_tol=1e-12):
                    fails.append(f"{where}: field data TimeValue {tv}, expected {t}")
    if nfiles == 0:
        fails.append(f"{path}: no blocks read")
    if "points" in exp and npts != exp["points"]:
        fails.append(f"{path}: {npts} points in the points blocks, expected {exp['points']}")
    if "cells" in exp:
        want = {k: v for k, v in exp["cells"].items() if v}
        if cells != want:
            fails.append(f"{path}: cells {cells}, expected {want}")
    print(f"{path}: {nfiles} blocks read by meshio, {npts} points, cells {cells}")


def check_pvd(path, exp, fails):
    try:
        root = ET.parse(path).getroot()
    except Exception as e:  # noqa: BLE001
        fails.append(f"{path}: not readable XML: {e}")
        return
    if root.get("type") != "Collection":
        fails.append(f"{path}: VTKFile type is {root.get('type')!r}, expected 'Collection'")
    sets = root.findall("./Collection/DataSet")
    times = []
    base = os.path.dirname(path)
    for ds in sets:
        t = float(ds.get("timestep"))
        times.append(t)
        f = os.path.join(base, ds.get("file"))
        if not os.path.exists(f):
            fails.append(f"{path}: lists {ds.get('file')}, which does not exist")
            continue
        if f.endswith(".vtm"):
            check_vtm(f, exp, fails, t)
        else:
            check_vtu(f, exp, fails)
    if any(b <= a for a, b in zip(times, times[1:])):
        fails.append(f"{path}: time values not increasing: {times}")
    if "times" in exp:
        want = exp["times"]
        ok = len(want) == len(times) and all(
            math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15) for a, b in zip(times, want))
        if not ok:
            fails.append(f"{path}: times {times}, expected {want}")
    print(f"{path}: {len(sets)} steps at t = {times}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("--expect", help="JSON file with expectations")
    ap.add_argument("--points", type=int)
    ap.add_argument("--cells", help="line=N,triangle=N,quad=N")
    ap.add_argument("--point-arrays", help="name:ncomp,...")
    ap.add_argument("--cell-arrays", help="name:ncomp,...")
    ap.add_argument("--times", help="t0,t1,... (for .pvd)")
    args = ap.parse_args()
    exp = {}
    if args.expect:
        with open(args.expect) as f:
            exp = json.load(f)
    if args.points is not None:
        exp["points"] = args.points
    if args.cells:
        exp["cells"] = parse_pairs(args.cells, int)
    if args.point_arrays:
        exp["point_arrays"] = parse_pairs(args.point_arrays, int)
    if args.cell_arrays:
        exp["cell_arrays"] = parse_pairs(args.cell_arrays, int)
    if args.times:
        exp["times"] = [float(t) for t in args.times.split(",")]
    if not os.path.exists(args.file):
        print(f"check_vtk: {args.file} does not exist", file=sys.stderr)
        return 1
    fails = []
    if args.file.endswith(".pvd"):
        check_pvd(args.file, exp, fails)
    elif args.file.endswith(".vtm"):
        check_vtm(args.file, exp, fails)
    else:
        check_vtu(args.file, exp, fails)
    if fails:
        print("FAILED:", file=sys.stderr)
        for f in fails:
            print("  " + f, file=sys.stderr)
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
