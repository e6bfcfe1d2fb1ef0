#!/usr/bin/env bash
# Kill and resume a scene run: run SCENE once uninterrupted, then again with checkpoints,
# killed with SIGKILL at KILLS seeded random times and resumed with --resume after each kill,
# and run to its end; then compare every output file (history CSV, VTU frames, PVD) byte for
# byte with the uninterrupted run. Exits 0 when all are identical.
#
#   scripts/kill-resume.sh SCENE [KILLS] [SEED] [CHECKPOINT_EVERY_S] [SCALE]
#   scripts/kill-resume.sh cases/beam/drop-2ms.yaml 10 1 20
#   scripts/kill-resume.sh tests/restart/nail-short.yaml 5 1 5 0.5
#
# Each run is killed after SCALE times the uninterrupted run's wall time divided by KILLS, times
# a uniform draw in [0.5, 1.5], so that the kills fall across the whole run. SCALE (default 1)
# below 1 leaves room for the time each resumed run spends before its first step and the steps
# it takes again after its checkpoint (the nail: reading the meshes, a 53 MB checkpoint). Needs target/release/impact-vv
# (cargo build --release). Output under reports/kill-resume/<scene name>/.
#
# LAUNCH runs every run under a launcher, e.g. over two MPI ranks (a build with `--features mpi`):
#   LAUNCH="mpirun -np 2" IMPACT_VV=target/release/impact-vv scripts/kill-resume.sh tests/restart/small-drop.yaml 5 1 0.5
# A kill then sends SIGKILL to every rank (the launcher's children) and to the launcher.
set -euo pipefail

scene=${1:?usage: scripts/kill-resume.sh SCENE [KILLS] [SEED] [CHECKPOINT_EVERY_S] [SCALE]}
kills=${2:-10}
seed=${3:-1}
every=${4:-20}
scale=${5:-1}
bin=${IMPACT_VV:-target/release/impact-vv}
read -r -a launch <<<"${LAUNCH:-}"
name=$(basename "$scene" .yaml)
out=reports/kill-resume/$name
rm -rf "$out"
mkdir -p "$out"

start=$(date +%s.%N)
"${launch[@]}" "$bin" scene "$scene" --out "$out/reference" >"$out/reference.log" 2>&1
full=$(echo "$(date +%s.%N) - $start" | bc)
echo "uninterrupted: $full s"

RANDOM=$seed
interrupted=0
for k in $(seq 1 "$kills"); do
    resume=()
    [ "$k" -gt 1 ] && resume=(--resume)
    "${launch[@]}" "$bin" scene "$scene" --out "$out/killed" --checkpoint-every "$every" "${resume[@]}" \
        >>"$out/killed.log" 2>&1 &
    pid=$!
    # Uniform in [0.5, 1.5] times scale * full / kills.
    after=$(echo "scale=3; $scale * $full / $kills * (0.5 + $RANDOM / 32767)" | bc)
    sleep "$after"
    # Under a launcher the ranks are its children: all of them die at once, then the launcher.
    victims=$(pgrep -P "$pid" || true)
    if kill -9 $victims "$pid" 2>/dev/null; then
        interrupted=$((interrupted + 1))
    fi
    wait "$pid" 2>/dev/null || true
    echo "kill $k after $after s: $(ls "$out"/killed/*-checkpoints 2>/dev/null | tr '\n' ' ')"
done
"${launch[@]}" "$bin" scene "$scene" --out "$out/killed" --checkpoint-every "$every" --resume >>"$out/killed.log" 2>&1
echo "$interrupted of $kills kills stopped a run"

status=0
for f in "$out/reference"/*; do
    base=$(basename "$f")
    if ! cmp -s "$f" "$out/killed/$base"; then
        echo "DIFFERS: $base"
        status=1
    fi
done
[ "$status" -eq 0 ] && echo "identical: every output file of the resumed run is that of the uninterrupted run"
exit "$status"
