# Opens an aqua run in ParaView with sensible defaults. Written by `aqua run` into the output
# directory; run it in that directory's context in either of these ways:
#
#   paraview --script=open_in_paraview.py          (the GUI)
#   pvpython open_in_paraview.py [options]          (an interactive window)
#   pvbatch  open_in_paraview.py --screenshot a.png (no window)
#
# or in the GUI with View > Python Shell > Run Script.
#
# What it shows: every object's lines (twines, ropes, chains) as thick lines coloured by
# `tension` [N] (0 where a member is slack), the net panels translucent, and the nodes that
# carry a point mass (sinkers, weights, [[point]] bodies) as spheres.
#
# Options:
#   --warp S          show the deformation scaled by S: the undeformed geometry
#                     (<scene>_reference.vtm) + Append Attributes + Warp By Vector (displacement);
#                     S = 1 gives the computed shape (the points of the series themselves).
#   --last            go to the last output step.
#   --screenshot PNG  save a picture of the view and quit.
#   --report JSON     write what was opened (blocks, time steps, tension range, warp error) to
#                     JSON and quit (used by aqua's tests).
#
# Points of the series hold the deformed positions; `displacement` is x - X. Do not apply
# Warp By Vector to the series itself (that adds the displacement twice); --warp does it the
# right way, from the reference geometry.

import glob
import json
import os
import sys

from paraview import servermanager as sm
from paraview.simple import (
    AppendAttributes,
    ColorBy,
    ExtractBlock,
    GetActiveViewOrCreate,
    GetAnimationScene,
    GetColorTransferFunction,
    GetScalarBar,
    PVDReader,
    Render,
    ResetCamera,
    SaveScreenshot,
    Show,
    Threshold,
    WarpByVector,
    XMLMultiBlockDataReader,
)


def parse_args(argv):
    opts = {"warp": None, "last": False, "screenshot": None, "report": None}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--warp" and i + 1 < len(argv):
            opts["warp"] = float(argv[i + 1])
            i += 1
        elif a == "--last":
            opts["last"] = True
        elif a == "--screenshot" and i + 1 < len(argv):
            opts["screenshot"] = argv[i + 1]
            i += 1
        elif a == "--report" and i + 1 < len(argv):
            opts["report"] = argv[i + 1]
            i += 1
        i += 1
    env = os.environ.get("AQUA_WARP")
    if opts["warp"] is None and env:
        opts["warp"] = float(env)
    return opts


# The output directory as `aqua run` wrote it (used when the script's own location is unknown,
# e.g. when a GUI runs it without __file__; a moved directory is found through __file__).
WRITTEN_IN = None


def run_dir():
    here = globals().get("__file__")
    candidates = [os.path.dirname(os.path.abspath(here))] if here else []
    candidates += [WRITTEN_IN, os.getcwd()]
    for d in candidates:
        if d and glob.glob(os.path.join(d, "*.pvd")):
            return d
    raise SystemExit(f"open_in_paraview: no .pvd found in {[d for d in candidates if d]}")


def find_pvd(d):
    try:
        with open(os.path.join(d, "run.json")) as f:
            p = json.load(f).get("pvd")
        if p:
            cand = os.path.join(d, os.path.basename(p))
            if os.path.exists(cand):
                return cand
    except (OSError, ValueError):
        pass
    found = sorted(glob.glob(os.path.join(d, "*.pvd")), key=os.path.getmtime)
    if not found:
        raise SystemExit(f"open_in_paraview: no .pvd in {d}")
    return found[-1]


def leaves(data, path=""):
    """(name, dataset) of every leaf of a multiblock, names as `object/kind`."""
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkMultiBlockDataSet

    out = []
    for i in range(data.GetNumberOfBlocks()):
        meta = data.GetMetaData(i)
        name = meta.Get(vtkCompositeDataSet.NAME()) if meta.Has(vtkCompositeDataSet.NAME()) else str(i)
        b = data.GetBlock(i)
        full = f"{path}/{name}" if path else name
        if isinstance(b, vtkMultiBlockDataSet):
            out.extend(leaves(b, full))
        elif b is not None:
            out.append((full, b))
    return out


def main(argv):
    opts = parse_args(argv)
    d = run_dir()
    pvd = find_pvd(d)
    stem = os.path.splitext(os.path.basename(pvd))[0]
    series = PVDReader(registrationName=stem, FileName=pvd)
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    times = [float(t) for t in series.TimestepValues] or [0.0]
    if opts["last"]:
        scene.AnimationTime = times[-1]

    source = series
    warp = None
    if opts["warp"] is not None:
        ref = XMLMultiBlockDataReader(
            registrationName=f"{stem}_reference",
            FileName=[os.path.join(d, f"{stem}_reference.vtm")],
        )
        both = AppendAttributes(registrationName="reference + step", Input=[ref, series])
        warp = WarpByVector(registrationName=f"warp x{opts['warp']:g}", Input=both)
        warp.Vectors = ["POINTS", "displacement"]
        warp.ScaleFactor = opts["warp"]
        source = warp

    view = GetActiveViewOrCreate("RenderView")
    lines = ExtractBlock(registrationName="lines", Input=source, Selectors=["//lines"])
    panels = ExtractBlock(registrationName="panels", Input=source, Selectors=["//panels"])
    points = ExtractBlock(registrationName="points", Input=source, Selectors=["//points"])
    masses = Threshold(registrationName="point masses", Input=points)
    masses.Scalars = ["POINTS", "point_mass"]
    masses.LowerThreshold = 1e-12
    masses.UpperThreshold = 1e300

    # Tension range over all steps, so the colour bar does not jump while playing.
    tmax = 0.0
    tmin = 0.0
    for t in times:
        lines.UpdatePipeline(t)
        r = lines.CellData["tension"].GetRange() if "tension" in lines.CellData.keys() else (0, 0)
        tmax = max(tmax, r[1])
        tmin = min(tmin, r[0])

    ld = Show(lines, view)
    ColorBy(ld, ("CELLS", "tension"))
    lut = GetColorTransferFunction("tension")
    lut.RescaleTransferFunction(0.0, max(tmax, 1e-9))
    lut.AutomaticRescaleRangeMode = "Never"
    ld.SetScalarBarVisibility(view, True)
    GetScalarBar(lut, view).Title = "tension [N]"
    GetScalarBar(lut, view).ComponentTitle = ""
    ld.LineWidth = 3.0
    ld.RenderLinesAsTubes = 1

    pd = Show(panels, view)
    pd.ColorArrayName = ["POINTS", ""]
    pd.AmbientColor = [0.55, 0.75, 0.9]
    pd.DiffuseColor = [0.55, 0.75, 0.9]
    pd.Opacity = 0.3

    md = Show(masses, view)
    md.ColorArrayName = ["POINTS", ""]
    md.SetRepresentationType("Points")
    md.PointSize = 8.0
    md.RenderPointsAsSpheres = 1
    md.AmbientColor = [0.9, 0.5, 0.1]
    md.DiffuseColor = [0.9, 0.5, 0.1]

    view.CameraPosition = [1.0, -1.5, 0.8]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    # A report alone needs no window (pvbatch on a machine without a display).
    if not opts["report"] or opts["screenshot"]:
        ResetCamera(view)
        Render(view)

    if opts["report"]:
        t_now = times[-1] if opts["last"] else times[0]
        series.UpdatePipeline(t_now)
        data = sm.Fetch(series)
        blocks = leaves(data)
        report = {
            "pvd": pvd,
            "times": times,
            "blocks": [name for name, _ in blocks],
            "points": sum(b.GetNumberOfPoints() for n, b in blocks if n.endswith("/points")),
            "cells": sum(b.GetNumberOfCells() for n, b in blocks if not n.endswith("/points")),
            "tension_range": [tmin, tmax],
            "line_arrays": sorted(
                {b.GetCellData().GetArrayName(k) for n, b in blocks if n.endswith("/lines")
                 for k in range(b.GetCellData().GetNumberOfArrays())}
            ),
        }
        if warp is not None:
            warp.UpdatePipeline(t_now)
            warped = dict(leaves(sm.Fetch(warp)))
            err = 0.0
            for name, b in blocks:
                w = warped[name]
                for k in range(b.GetNumberOfPoints()):
                    p = b.GetPoint(k)
                    q = w.GetPoint(k)
                    err = max(err, max(abs(p[j] - q[j]) for j in range(3)))
            report["warp_scale"] = opts["warp"]
            report["warp_max_error"] = err
        with open(opts["report"], "w") as f:
            json.dump(report, f, indent=1)
    if opts["screenshot"]:
        SaveScreenshot(opts["screenshot"], view, ImageResolution=[1200, 800])
    return view


_view = main(sys.argv[1:])
# pvpython: keep the window open until it is closed. The GUI (which runs the script with an
# empty sys.argv[0]) and pvbatch need nothing more.
_interactive = not any(a in sys.argv for a in ("--screenshot", "--report"))
if _interactive and sys.argv[:1] and sys.argv[0].endswith(".py") \
        and not getattr(__import__("paraview"), "fromGUI", False):
    try:
        from paraview.simple import Interact

        Interact(_view)
    except Exception:  # noqa: BLE001 - pvbatch has no interactor
        pass
