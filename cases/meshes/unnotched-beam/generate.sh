#!/bin/sh
# Regenerates the unnotched beam meshes from unnotched_beam.geo and unnotched_beam_graded.geo (Gmsh 4.15.2: `pip install gmsh==4.15.2`).
set -eu
cd "$(dirname "$0")"
gmsh unnotched_beam.geo -3 -format msh41 -bin -o unnotched_beam_d50.msh
gmsh unnotched_beam_graded.geo -3 -format msh41 -bin -o unnotched_beam_d50_graded.msh
