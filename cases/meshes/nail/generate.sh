#!/bin/sh
# Regenerates the meshes of the nail-penetration case from their .geo files
# (Gmsh 4.15.2: `pip install gmsh==4.15.2`), then checks them (check_meshes.py, needs numpy).
# Gmsh exits with status 0 even when a script stops on Error(...), hence the grep of its log.
set -eu
cd "$(dirname "$0")"
for body in nail block plate; do
  gmsh "$body.geo" -3 -format msh41 -bin -o "$body.msh" > "$body.log" 2>&1
  if grep -q '^Error' "$body.log"; then
    grep '^Error' "$body.log" >&2
    rm -f "$body.msh"
    exit 1
  fi
  rm -f "$body.log"
done
# The nail case's block: 0.5 mm within 4 mm of the nail's path for 25 mm (block.geo's parameters).
gmsh block.geo -3 -format msh41 -bin -setnumber h_fine 0.0005 -setnumber r_fine 0.004 \
  -setnumber growth 0.2 -setnumber fine_depth 0.025 -o block-path.msh > block-path.log 2>&1
if grep -q '^Error' block-path.log; then
  grep '^Error' block-path.log >&2
  rm -f block-path.msh
  exit 1
fi
rm -f block-path.log
python3 check_meshes.py
