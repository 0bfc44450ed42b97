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
# `tension` [N] (0 where a member is slack), the net panels translucent (net triangles coloured
# by the tension of one U twine, `twine_tension_u` [N]), and the nodes that
# carry a point mass (sinkers, weights, [[point]] bodies) as spheres.
#
# Options:
#   --warp S          show the deformation scaled by S at every time step: X + S * displacement
#                     (X the undeformed geometry); S = 1 gives the computed shape (the points of
#                     the series themselves), S = 0 the undeformed geometry.
#   --last            go to the last output step.
#   --screenshot PNG  save a picture of the view and quit.
#   --size WxH        the view's size in pixels (default 1600x900; also the screenshot's size).
#   --report JSON     write what was opened (blocks, time steps, tension range, the warp checked
#                     at the first and last step) to JSON and quit (used by aqua's tests).
#
# Points of the series hold the deformed positions x = X + displacement. So --warp S is Warp By
# Vector (`displacement`) with scale factor S - 1 applied to the series itself: x + (S - 1) d =
# X + S d, recomputed whenever the time changes. (Warp By Vector with scale S on the series
# would add the displacement twice.)

import glob
import json
import os
import sys

from paraview import servermanager as sm
from paraview.simple import (
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
    opts = {"warp": None, "last": False, "screenshot": None, "report": None, "size": [1600, 900]}
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
        elif a == "--size" and i + 1 < len(argv):
            try:
                w, h = (int(v) for v in argv[i + 1].lower().split("x"))
            except ValueError:
                raise SystemExit(f"open_in_paraview: --size {argv[i + 1]}: expected WxH, "
                                 "e.g. 1600x900")
            if w < 200 or h < 200:
                raise SystemExit(f"open_in_paraview: --size {argv[i + 1]}: at least 200x200")
            opts["size"] = [w, h]
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
        # x + (S - 1) d = X + S d from the series alone, so it follows the time. (Append
        # Attributes of the time-independent reference and the series does not: it keeps the
        # displacement of the first time it ran.)
        warp = WarpByVector(registrationName=f"warp x{opts['warp']:g}", Input=series)
        warp.Vectors = ["POINTS", "displacement"]
        warp.ScaleFactor = opts["warp"] - 1.0
        source = warp

    view = GetActiveViewOrCreate("RenderView")
    # A fixed view size: a screenshot is then rendered at the size the colour bar was laid out
    # for (saving a small default view at a large resolution scales the bar's text up).
    view.ViewSize = opts["size"]
    view.OrientationAxesVisibility = 1
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
    bar = style_bar(GetScalarBar(lut, view), "tension [N]", 0.89)
    ld.LineWidth = 3.0
    ld.RenderLinesAsTubes = 1

    pd = Show(panels, view)
    panels.UpdatePipeline(times[0])
    if "twine_tension_u" in panels.CellData.keys():
        # Net triangles carry the twines themselves (no twine lines): colour them by the
        # tension of one U twine, with its range over all steps.
        umax = 0.0
        for t in times:
            panels.UpdatePipeline(t)
            umax = max(umax, panels.CellData["twine_tension_u"].GetRange()[1])
        ColorBy(pd, ("CELLS", "twine_tension_u"))
        plut = GetColorTransferFunction("twine_tension_u")
        plut.RescaleTransferFunction(0.0, max(umax, 1e-9))
        plut.AutomaticRescaleRangeMode = "Never"
        pd.SetScalarBarVisibility(view, True)
        style_bar(GetScalarBar(plut, view), "U twine tension [N]", 0.03)
    else:
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
        # ResetCamera fits the bounding sphere; the model then fills about a third of the
        # frame: come closer.
        view.GetActiveCamera().Dolly(1.6)
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
            report["warp_scale"] = opts["warp"]
            report["warp"] = warp_check(d, stem, series, warp, opts["warp"],
                                        [times[0], times[-1]])
        report["view_size"] = list(view.ViewSize)
        report["scalar_bar"] = {
            "position": list(bar.Position),
            "length": float(bar.ScalarBarLength),
            "title": str(bar.Title),
        }
        with open(opts["report"], "w") as f:
            json.dump(report, f, indent=1)
    if opts["screenshot"]:
        SaveScreenshot(opts["screenshot"], view, ImageResolution=opts["size"])
    return view


def style_bar(bar, title, x):
    """A vertical colour bar with `title`, its left edge at `x` (fraction of the view), legible at
    the fixed view size; returns it."""
    bar.Title = title
    bar.ComponentTitle = ""
    bar.WindowLocation = "Any Location"
    bar.Orientation = "Vertical"
    bar.Position = [x, 0.1]
    bar.ScalarBarLength = 0.6
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.RangeLabelFormat = "%-#.3g"
    return bar


def points_of(data):
    """{block: [(x, y, z), ...]} of a fetched multiblock."""
    return {name: [b.GetPoint(k) for k in range(b.GetNumberOfPoints())]
            for name, b in leaves(data)}


def warp_check(d, stem, series, warp, scale, times):
    """At each of `times`: the warped points against the series' own points x and against
    X + scale * displacement (X read from <stem>_reference.vtm), and how far the warped
    geometry moved from the first of `times` (for the report of --report)."""
    ref = XMLMultiBlockDataReader(FileName=[os.path.join(d, f"{stem}_reference.vtm")])
    ref.UpdatePipeline()
    x0 = points_of(sm.Fetch(ref))
    out = []
    first = None
    for t in times:
        series.UpdatePipeline(t)
        step = sm.Fetch(series)
        x = points_of(step)
        disp = {name: [b.GetPointData().GetArray("displacement").GetTuple3(k)
                       for k in range(b.GetNumberOfPoints())] for name, b in leaves(step)}
        warp.UpdatePipeline(t)
        w = points_of(sm.Fetch(warp))
        err_series = err_formula = 0.0
        for name, pts in x.items():
            for k, p in enumerate(pts):
                q = w[name][k]
                want = [x0[name][k][j] + scale * disp[name][k][j] for j in range(3)]
                err_series = max(err_series, max(abs(p[j] - q[j]) for j in range(3)))
                err_formula = max(err_formula, max(abs(want[j] - q[j]) for j in range(3)))
        if first is None:
            first = (x, w)
        moved_series = max(max(abs(p[j] - first[0][n][k][j]) for j in range(3))
                           for n, pts in x.items() for k, p in enumerate(pts))
        moved_warp = max(max(abs(p[j] - first[1][n][k][j]) for j in range(3))
                         for n, pts in w.items() for k, p in enumerate(pts))
        out.append({
            "t": t,
            "max_error_vs_series": err_series,
            "max_error_vs_reference_plus_scaled_displacement": err_formula,
            "series_moved_since_first": moved_series,
            "warp_moved_since_first": moved_warp,
        })
    return out


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
