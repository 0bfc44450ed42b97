#!/usr/bin/env python3
"""Independent check of an `aqua run` output directory with the VTK Python package.

Usage:
  check_series.py RUN.pvd [--expect EXPECT.json] [--single MESH.vtm]

Reads the `.pvd` (XML), every `.vtm` it lists and the undeformed `<stem>_reference.vtm` with
VTK's own readers (vtkXMLMultiBlockDataReader, not the Rust code that wrote them) and checks:

* the `.pvd` lists existing `.vtm` files at increasing times, and every `.vtm` in the
  directory is listed;
* block names `object/kind` (kind = lines, panels, points) — exactly `blocks` if expected;
* array names per kind (`point_arrays`, `line_arrays`, `panel_arrays` must be present);
* every value finite; `tension` >= 0, `slack` in {0, 1}, `tension` = max(`axial_force`, 0) and
  `slack` = (`axial_force` <= 0);
* field data: `TimeValue` (= the `.pvd` time) and no string arrays (which meshio cannot read);
* the name tables of run.json (`run_json`): every `group_id`/`role_id`/`object_id` has a name,
  `names.block_names` = the block names of every step, `names.block_objects` has one object
  name per block, and every block name (`object/kind`) uses only the characters ParaView keeps
  in its hierarchy (ASCII letters, digits, `_`);
* the `points` blocks partition the nodes (`node_id` 0..N-1 once each) and the lines/panels
  blocks hold every element once (`element_id`, `panel_id`);
* `point_sums` {array: value}: the sum of a point array over the `points` blocks;
* the sums over blocks equal the model's counts: `points`, `cells` {line, triangle, quad}
  from EXPECT.json, and/or those of `--single MESH.vtm` (the same model's geometry written by
  `aqua mesh --scene ... --out`: points of its `points` blocks, cells of the others);
* reference points + `displacement` = the step's points.

Exit status 0 when every check passes, 1 otherwise (failures listed on stderr).
"""
import argparse
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkMultiBlockDataSet
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader

VTK_TYPES = {1: "vertex", 3: "line", 5: "triangle", 9: "quad"}


def leaves(data, path=""):
    out = []
    for i in range(data.GetNumberOfBlocks()):
        meta = data.GetMetaData(i) if data.HasMetaData(i) else None
        name = meta.Get(vtkCompositeDataSet.NAME()) if meta and meta.Has(vtkCompositeDataSet.NAME()) else None
        b = data.GetBlock(i)
        full = f"{path}/{name}" if path else str(name)
        if isinstance(b, vtkMultiBlockDataSet):
            out.extend(leaves(b, full))
        elif b is not None:
            out.append((full, b))
    return out


def read_vtm(path):
    r = vtkXMLMultiBlockDataReader()
    r.SetFileName(path)
    r.Update()
    return leaves(r.GetOutput())


def arr(data, name):
    a = data.GetArray(name)
    return None if a is None else vtk_to_numpy(a)


def cell_counts(grid):
    counts = {}
    for k in range(grid.GetNumberOfCells()):
        t = VTK_TYPES.get(grid.GetCellType(k), str(grid.GetCellType(k)))
        counts[t] = counts.get(t, 0) + 1
    return counts


def check_step(path, t, exp, fails, ref=None, tables=None):
    blocks = read_vtm(path)
    names = [n for n, _ in blocks]
    if not blocks:
        fails.append(f"{path}: no blocks")
        return None
    if "blocks" in exp and names != exp["blocks"]:
        fails.append(f"{path}: blocks {names}, expected {exp['blocks']}")
    npts = 0
    cells = {}
    node_ids = []
    point_sums = {}
    elem_ids = []
    panel_ids = []
    for name, b in blocks:
        kind = name.rsplit("/", 1)[-1]
        if kind not in ("lines", "panels", "points"):
            fails.append(f"{path}: block {name}: kind {kind!r} is not lines, panels or points")
        if not all(p and all(c.isascii() and (c.isalnum() or c == "_") for c in p)
                   and not p[0].isdigit() for p in name.split("/")):
            fails.append(f"{path}: block {name}: ParaView drops characters of this name")
        fd = b.GetFieldData()
        for k in range(fd.GetNumberOfArrays()):
            a = fd.GetAbstractArray(k)
            if a.GetDataTypeAsString() == "string" or a.IsA("vtkStringArray"):
                fails.append(f"{path}: block {name}: string field data {a.GetName()!r} "
                             "(meshio cannot read it)")
        if t is not None:
            tv = fd.GetArray("TimeValue")
            if tv is None or not math.isclose(tv.GetValue(0), t, rel_tol=1e-12, abs_tol=1e-12):
                fails.append(f"{path}: block {name}: TimeValue {tv and tv.GetValue(0)} != {t}")
        pts = vtk_to_numpy(b.GetPoints().GetData()) if b.GetNumberOfPoints() else np.zeros((0, 3))
        if not np.all(np.isfinite(pts)):
            fails.append(f"{path}: block {name}: non-finite points")
        pd, cd = b.GetPointData(), b.GetCellData()
        for a in exp.get("point_arrays", []):
            if pd.GetArray(a) is None:
                fails.append(f"{path}: block {name}: point array {a!r} missing")
        want = exp.get(f"{kind[:-1]}_arrays", []) if kind != "points" else []
        for a in want:
            if cd.GetArray(a) is None:
                fails.append(f"{path}: block {name}: cell array {a!r} missing")
        for data in (pd, cd):
            for k in range(data.GetNumberOfArrays()):
                v = vtk_to_numpy(data.GetArray(k))
                if not np.all(np.isfinite(v)):
                    fails.append(f"{path}: block {name}: array {data.GetArrayName(k)} not finite")
        for key, table in (("group_id", "group_names"), ("role_id", "role_names"),
                           ("object_id", "object_names")):
            ids = arr(cd, key)
            if ids is not None and len(ids) and tables and ids.max() >= len(tables[table]):
                fails.append(f"{path}: block {name}: {key} {ids.max()} has no name in {table}")
        if kind == "lines":
            ten, sl, ax = arr(cd, "tension"), arr(cd, "slack"), arr(cd, "axial_force")
            if ten is not None and sl is not None and ax is not None:
                if np.any(ten < 0):
                    fails.append(f"{path}: block {name}: negative tension {ten.min()}")
                if not set(np.unique(sl)) <= {0, 1}:
                    fails.append(f"{path}: block {name}: slack not 0/1")
                if not np.allclose(ten, np.maximum(ax, 0.0), rtol=0, atol=0):
                    fails.append(f"{path}: block {name}: tension != max(axial_force, 0)")
                if not np.array_equal(sl.astype(bool), ax <= 0.0):
                    fails.append(f"{path}: block {name}: slack != (axial_force <= 0)")
            ids = arr(cd, "element_id")
            if ids is not None:
                elem_ids.extend(ids.tolist())
        if kind == "panels":
            ids = arr(cd, "panel_id")
            if ids is not None:
                panel_ids.extend(ids.tolist())
        if kind == "points":
            npts += b.GetNumberOfPoints()
            ids = arr(pd, "node_id")
            if ids is not None:
                node_ids.extend(ids.tolist())
            for a in exp.get("point_sums", {}):
                v = arr(pd, a)
                point_sums[a] = point_sums.get(a, 0) + (float(v.sum()) if v is not None else 0.0)
            if b.GetNumberOfCells() != b.GetNumberOfPoints():
                fails.append(f"{path}: block {name}: {b.GetNumberOfCells()} vertices for "
                             f"{b.GetNumberOfPoints()} points")
        else:
            for k, v in cell_counts(b).items():
                cells[k] = cells.get(k, 0) + v
        if ref is not None:
            r = ref.get(name)
            if r is None:
                fails.append(f"{path}: block {name} missing in the reference")
            else:
                disp = arr(pd, "displacement")
                rp = vtk_to_numpy(r.GetPoints().GetData())
                if disp is None or rp.shape != pts.shape:
                    fails.append(f"{path}: block {name}: reference and step points do not match")
                else:
                    err = np.abs(rp + disp - pts).max() if len(pts) else 0.0
                    scale = max(1.0, np.abs(pts).max() if len(pts) else 1.0)
                    if err > 1e-9 * scale:
                        fails.append(f"{path}: block {name}: reference + displacement differs "
                                     f"from the points by {err}")
    if sorted(node_ids) != list(range(len(node_ids))):
        fails.append(f"{path}: points blocks do not hold every node once")
    if sorted(elem_ids) != list(range(len(elem_ids))):
        fails.append(f"{path}: lines blocks do not hold every element once")
    if sorted(panel_ids) != list(range(len(panel_ids))):
        fails.append(f"{path}: panels blocks do not hold every panel once")
    for a, want in exp.get("point_sums", {}).items():
        if not math.isclose(point_sums.get(a, 0.0), want, rel_tol=1e-9, abs_tol=1e-9):
            fails.append(f"{path}: sum of point array {a} over the points blocks is "
                         f"{point_sums.get(a)}, expected {want}")
    if "points" in exp and npts != exp["points"]:
        fails.append(f"{path}: {npts} points in the points blocks, expected {exp['points']}")
    if "cells" in exp:
        want = {k: v for k, v in exp["cells"].items() if v}
        if cells != want:
            fails.append(f"{path}: cells {cells}, expected {want}")
    print(f"{path}: {len(blocks)} blocks, {npts} points, cells {cells}")
    return {"names": names, "points": npts, "cells": cells}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pvd")
    ap.add_argument("--expect")
    ap.add_argument("--single", help="the same model's geometry (.vtm of aqua mesh)")
    args = ap.parse_args()
    exp = {}
    if args.expect:
        with open(args.expect) as f:
            exp = json.load(f)
    fails = []
    if args.single:
        single = {"points": 0, "cells": {}}
        for name, g in read_vtm(args.single):
            if name.rsplit("/", 1)[-1] == "points":
                single["points"] += g.GetNumberOfPoints()
                continue
            for k, v in cell_counts(g).items():
                single["cells"][k] = single["cells"].get(k, 0) + v
        print(f"{args.single}: the model, {single['points']} points, cells {single['cells']}")
        for k in ("points", "cells"):
            if k in exp and exp[k] != single[k]:
                fails.append(f"expectation {k} {exp[k]} differs from the --single geometry {single[k]}")
            exp[k] = single[k]
    try:
        root = ET.parse(args.pvd).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"FAILED:\n  {args.pvd}: not readable: {e}", file=sys.stderr)
        return 1
    base = os.path.dirname(os.path.abspath(args.pvd))
    stem = os.path.splitext(os.path.basename(args.pvd))[0]
    names = None
    if "run_json" in exp:
        with open(exp["run_json"]) as f:
            names = json.load(f).get("names", {})
        for k in ("object_names", "group_names", "role_names", "block_names", "block_objects"):
            if not isinstance(names.get(k), list):
                fails.append(f"run.json names.{k} missing")
                names[k] = []
    ref_path = os.path.join(base, f"{stem}_reference.vtm")
    ref = None
    if os.path.exists(ref_path):
        ref = dict(read_vtm(ref_path))
        check_step(ref_path, None, {k: v for k, v in exp.items() if k in ("blocks", "points",
                                                                         "cells")}, fails)
    else:
        fails.append(f"{ref_path} (the undeformed geometry) is missing")
    sets = root.findall("./Collection/DataSet")
    times = []
    listed = set()
    result = None
    for ds in sets:
        t = float(ds.get("timestep"))
        times.append(t)
        f = os.path.join(base, ds.get("file"))
        listed.add(os.path.basename(f))
        if not os.path.exists(f):
            fails.append(f"{args.pvd}: lists {ds.get('file')}, which does not exist")
            continue
        result = check_step(f, t, exp, fails, ref, names) or result
    on_disk = {n for n in os.listdir(base) if n.endswith(".vtm") and n.startswith(stem + "_")
               and n != f"{stem}_reference.vtm"}
    if on_disk != listed:
        fails.append(f"{args.pvd}: lists {sorted(listed)}, directory has {sorted(on_disk)}")
    if any(b <= a for a, b in zip(times, times[1:])):
        fails.append(f"{args.pvd}: times not increasing: {times}")
    if "times" in exp:
        want = exp["times"]
        if len(want) != len(times) or not all(
                math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12) for a, b in zip(times, want)):
            fails.append(f"{args.pvd}: times {times}, expected {want}")
    if names is not None and result is not None:
        if len(names["block_objects"]) != len(names["block_names"]):
            fails.append(f"run.json names.block_objects has {len(names['block_objects'])} "
                         f"entries for {len(names['block_names'])} blocks")
        if not set(names["block_objects"]) <= set(names["object_names"]) | {
                f"{o}#{k}" for o in names["object_names"] for k in range(1000)}:
            fails.append(f"run.json names.block_objects {names['block_objects']} are not "
                         f"object names {names['object_names']}")
        if names.get("block_names") != result["names"]:
            fails.append(f"run.json names.block_names {names.get('block_names')} != "
                         f"{result['names']}")
    print(f"{args.pvd}: {len(sets)} steps at t = {times}")
    if fails:
        print("FAILED:", file=sys.stderr)
        for f in fails:
            print("  " + f, file=sys.stderr)
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
