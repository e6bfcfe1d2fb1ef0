#!/bin/sh
# Regenerates the notched beam meshes from notched_beam.geo and notched_beam_graded.geo (Gmsh 4.15.2: `pip install gmsh==4.15.2`).
set -eu
cd "$(dirname "$0")"
gmsh notched_beam.geo -3 -format msh41 -bin -o notched_beam_d50.msh
gmsh notched_beam_graded.geo -3 -format msh41 -bin -o notched_beam_d50_graded.msh
gmsh notched_beam_graded.geo -3 -setnumber nw 0.00125 -format msh41 -bin -o notched_beam_d50_graded_n1.25.msh
