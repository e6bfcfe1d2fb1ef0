#!/usr/bin/env bash
# The drop tests on another concrete: copies of the catalogue's `beam/drop-*` cases (those given,
# or all) with the beam's material file replaced by CONCRETE, every other line as it is but the
# `known_failure` (its numbers are the shipped concrete's) and the ids (`<stem>/drop-...`, the
# stem of CONCRETE), run one after the other into reports/drop-tests-on-<stem>/. Each case is
# judged on its own bands, so the report shows where the concrete meets them.
#
#   scripts/drop-tests-on.sh CONCRETE [CASE ...]
#   scripts/drop-tests-on.sh cases/materials/thesis-concrete-tension-boundary.yaml drop-2ms drop-4ms-gmsh
#
# Needs target/release/impact-vv (or IMPACT_VV). Prints one line per case and variant with its
# failed metrics; the full report is the run's index.html.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${IMPACT_VV:-target/release/impact-vv}")
[ $# -gt 0 ] || { echo "usage: scripts/drop-tests-on.sh CONCRETE [CASE ...]" >&2; exit 2; }
concrete=$1
shift
[ -f "$concrete" ] || { echo "no concrete file $concrete" >&2; exit 2; }
stem=$(basename "$concrete" .yaml)
out=$PWD/reports/drop-tests-on-$stem
catalogue=$out/cases
rm -rf "$catalogue"
mkdir -p "$catalogue/beam" "$catalogue/materials"
# Relative paths in the cases (../materials, ../meshes) resolve as in the catalogue; the
# catalogue reads every file outside materials/ and meshes/ as a case.
ln -sfn "$PWD/cases/meshes" "$catalogue/meshes"
cp "$concrete" "$catalogue/materials/concrete-under-test.yaml"
if [ $# -gt 0 ]; then
  cases=("$@")
else
  cases=()
  for f in cases/beam/drop-*.yaml; do cases+=("$(basename "$f" .yaml)"); done
fi
for c in "${cases[@]}"; do
  src=cases/beam/$c.yaml
  [ -f "$src" ] || { echo "no case $src" >&2; exit 2; }
  grep -q 'file: ../materials/thesis-concrete.yaml' "$src" || {
    echo "$src: no beam of ../materials/thesis-concrete.yaml to replace" >&2
    exit 2
  }
  sed -e 's#file: ../materials/thesis-concrete.yaml#file: ../materials/concrete-under-test.yaml#' \
    -e "s#^id: beam/#id: $stem/#" -e '/^known_failure:/d' "$src" >"$catalogue/beam/$c.yaml"
  "$bin" run --catalogue "$catalogue" --reports "$out/runs" --serial "$catalogue/beam/$c.yaml" \
    >"$out/$c.log" 2>&1 || true
  grep -E '^(pass|fail) ' "$out/$c.log" || { echo "$c: no verdict, see $out/$c.log" >&2; }
done
echo "reports under $out/runs"
