"""Counts the cells ParaView's Extract Block selects from a multiblock file, per selector.

Usage (ParaView's Python):
  pvbatch paraview_select.py FILE.vtm OUT.json SELECTOR...

Writes {"hierarchy": [the names ParaView gives the blocks], "cells": {selector: cells}} to
OUT.json. Used by aqua-cli/tests/cli_run.rs to check that the selectors docs/guide/paraview.md documents
select what they say in real ParaView (which drops characters other than ASCII letters, digits
and `_` from block names).
"""
import json
import sys

from paraview import servermanager as sm
from paraview.simple import ExtractBlock, XMLMultiBlockDataReader


def cells(data):
    n = 0
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        n += it.GetCurrentDataObject().GetNumberOfCells()
        it.GoToNextItem()
    return n


def main(argv):
    path, out, selectors = argv[0], argv[1], argv[2:]
    reader = XMLMultiBlockDataReader(FileName=[path])
    reader.UpdatePipeline()
    hierarchy = reader.GetDataInformation().DataInformation.GetHierarchy()
    names = [hierarchy.GetNodeName(hierarchy.GetChild(0, k))
             for k in range(hierarchy.GetNumberOfChildren(0))]
    result = {}
    for sel in selectors:
        e = ExtractBlock(Input=reader, Selectors=[sel])
        e.UpdatePipeline()
        result[sel] = cells(sm.Fetch(e))
    with open(out, "w") as f:
        json.dump({"hierarchy": names, "cells": result}, f, indent=1)


main(sys.argv[1:])
