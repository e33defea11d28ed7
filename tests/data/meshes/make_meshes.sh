#!/bin/sh
# Regenerates the committed test meshes (Gmsh .msh in four encodings, meshio
# .vtu/.vtk conversions) and expected.json from the .geo files in this folder.
# Needs Debian's python3 with python3-gmsh (Gmsh 4.8) and python3-meshio.
set -e
cd "$(dirname "$0")"
rm -f ./*.msh ./*.vtu ./*.vtk expected.json
exec /usr/bin/python3 make_meshes.py
