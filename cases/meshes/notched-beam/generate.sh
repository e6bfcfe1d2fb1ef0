#!/bin/sh
# Regenerates the notched beam mesh from notched_beam.geo (Gmsh 4.15.2: `pip install gmsh==4.15.2`).
set -eu
cd "$(dirname "$0")"
gmsh notched_beam.geo -3 -format msh41 -bin -o notched_beam_d50.msh
