#!/usr/bin/env bash
# Both D = 50 mm beams of Gregoire et al. (2013), the half-notched and the unnotched, for each
# pair of tensile strength f_t (MPa) and fracture energy G_F (N/m): the batch's targets
# (cases/materials/gregoire-2013-targets.yaml) with f_t and G_F replaced are calibrated
# (`impact-vv calibrate`), and the 10 mm slices of the graded meshes
# (cases/examples/*-gregoire-d50-slice-10mm.yaml, implicit static path under CMOD control, crack
# band across the crack) run on that concrete. Prints each pair's peaks over 50 mm, their CMODs
# and the ratio unnotched / half-notched, against the tests' mean curves 978.6 N and 4649.2 N
# (ratio 4.75).
#
#   scripts/gregoire-pair-sweep.sh FT,GF [FT,GF ...]
#   scripts/gregoire-pair-sweep.sh 4.3,100 5.0,60 6.0,30
#
# Needs target/release/impact-vv (or IMPACT_VV) and Gmsh 4.15.2 (`pip install gmsh==4.15.2`) for
# the slice meshes, and bc. Each pair is a calibration (about a minute) and the two slices' static
# paths. Output under reports/gregoire-pair-sweep/.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${IMPACT_VV:-target/release/impact-vv}")
[ $# -gt 0 ] || { echo "usage: scripts/gregoire-pair-sweep.sh FT,GF [FT,GF ...]" >&2; exit 2; }
out=$PWD/reports/gregoire-pair-sweep
mkdir -p "$out/meshes"
repo=$PWD

# The slice meshes: one 10 mm layer of each graded mesh (the commands in the slices' headers).
notched_mesh=$out/meshes/notched_beam_d50_slice_w10.msh
unnotched_mesh=$out/meshes/unnotched_beam_d50_slice_w10.msh
[ -s "$notched_mesh" ] || gmsh cases/meshes/notched-beam/notched_beam_graded.geo -setnumber nw 0.00125 \
  -setnumber W 0.01 -setnumber nz 1 -3 -format msh41 -bin -o "$notched_mesh" >"$out/meshes/gmsh.log"
[ -s "$unnotched_mesh" ] || gmsh cases/meshes/unnotched-beam/unnotched_beam_graded.geo -setnumber W 0.01 \
  -setnumber nz 1 -3 -format msh41 -bin -o "$unnotched_mesh" >>"$out/meshes/gmsh.log"

# Peak of the load reaction over 50 mm (the slice is 10 mm) and the CMOD at it.
peak() {
  python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
load = next(c for c in rows[0] if c.startswith("load") and "reaction" in c and c.endswith("_y"))
left = next(c for c in rows[0] if c.startswith("mouth_left") and c.endswith("_x"))
right = next(c for c in rows[0] if c.startswith("mouth_right") and c.endswith("_x"))
best = max(rows, key=lambda r: abs(float(r[load])))
print(f"{abs(float(best[load])) * 5:.1f} {1e3 * (float(best[right]) - float(best[left])):.4f}")
PY
}

printf '%-8s %-8s %12s %10s %12s %10s %7s\n' "f_t" "G_F" "notched_N" "cmod_mm" "unnotched_N" "cmod_mm" "ratio"
for pair in "$@"; do
  ft=${pair%,*} gf=${pair#*,}
  dir=$out/ft${ft}_gf${gf}
  mkdir -p "$dir"
  # f_t and G_F replaced; the bands that follow from them scaled with them: the peak strain's
  # with f_t, the softening end's (a multiple of G_F / f_t) with G_F / f_t.
  python3 - "$ft" "$gf" cases/materials/gregoire-2013-targets.yaml >"$dir/targets.yaml" <<'PY'
import re, sys
ft, gf, path = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
s_ft, s_end = ft / 3.9, (gf / 143.2) / (ft / 3.9)
def scale(line, key, k):
    m = re.match(rf"^(  {key}: )\[([^,]+), ([^\]]+)\]", line)
    return f"{m.group(1)}[{float(m.group(2)) * k:.5g}, {float(m.group(3)) * k:.5g}]\n" if m else line
out = []
for line in open(path):
    line = re.sub(r"^  ft: .*", f"  ft: {ft}e6", line)
    line = re.sub(r"^  gf: .*", f"  gf: {gf}", line)
    line = scale(line, "ft_strain", s_ft)
    line = scale(line, "softening_end", s_end)
    out.append(line)
sys.stdout.write("".join(out))
PY
  "$bin" calibrate --targets "$dir/targets.yaml" --out "$dir/concrete.yaml" >"$dir/calibrate.log" 2>&1
  results=()
  for beam in notched unnotched; do
    mesh=$notched_mesh
    [ $beam = unnotched ] && mesh=$unnotched_mesh
    sed -e "s#file: ../materials/gregoire-2013-concrete.yaml#file: $dir/concrete.yaml#" \
      -e "s#gmsh: ../meshes/[a-z-]*/[a-z0-9_]*.msh#gmsh: $mesh#" \
      "$repo/cases/examples/$beam-gregoire-d50-slice-10mm.yaml" >"$dir/$beam.yaml"
    "$bin" scene "$dir/$beam.yaml" --no-fields --out "$dir/$beam" >"$dir/$beam.log" 2>&1
    results+=("$(peak "$(ls "$dir/$beam"/*_history.csv)")")
  done
  read -r pn cn <<<"${results[0]}"
  read -r pu cu <<<"${results[1]}"
  printf '%-8s %-8s %12s %10s %12s %10s %7.3f\n' "$ft" "$gf" "$pn" "$cn" "$pu" "$cu" "$(echo "$pu / $pn" | bc -l)"
done
