#!/bin/sh
# Regenerates the unstructured beam mesh from beam.geo (Gmsh 4.15.2: `pip install gmsh==4.15.2`).
set -eu
cd "$(dirname "$0")"
gmsh beam.geo -3 -format msh41 -bin -o beam_50mm.msh
