#!/bin/sh
# Regenerates the mesh from short_notched_beam_d100_graded.geo (Gmsh 4.15.2: `pip install gmsh==4.15.2`).
set -eu
cd "$(dirname "$0")"
gmsh short_notched_beam_d100_graded.geo -3 -format msh41 -bin -o short_notched_beam_d100_graded.msh
