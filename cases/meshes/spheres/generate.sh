#!/bin/sh
# Regenerates the three sphere meshes from sphere.geo (Gmsh 4.8.4: `apt-get install gmsh`).
set -eu
cd "$(dirname "$0")"
gmsh sphere.geo -setnumber level 0 -3 -format msh41 -bin -o sphere_coarse.msh
gmsh sphere.geo -setnumber level 1 -3 -format msh41 -bin -o sphere_medium.msh
gmsh sphere.geo -setnumber level 2 -3 -format msh41 -bin -o sphere_fine.msh
