#!/bin/sh
# Regenerates the three meshes of the nail-penetration case from their .geo files
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
python3 check_meshes.py
