#!/usr/bin/env bash
# Peak resident memory of each parkslam command at two input sizes
# (docs/robustness.md, "Resources"): a command's memory must grow with its
# input, not with anything else. Needs GNU time (/usr/bin/time).
#   usage: scripts/memory_audit.sh [PATH/TO/parkslam]   (about half a minute)
set -euo pipefail
parkslam=$(realpath "${1:-build/bin/parkslam}")
[ -x /usr/bin/time ] || { echo "memory_audit.sh: /usr/bin/time is missing (apt install time)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
peak() {
  local name=$1; shift
  if ! /usr/bin/time -f "%M %e" -o t "$@" > /dev/null 2> err; then
    echo "memory_audit.sh: $name failed:" >&2; cat err >&2; exit 1
  fi
  read -r kb s < t
  printf "%-28s %8.1f MB %7.2f s\n" "$name" "$(echo "$kb / 1024" | bc -l)" "$s"
}
printf "%-28s %11s %9s\n" command "peak RSS" time
for laps in 1 4; do
  peak "simulate (laps $laps)" "$parkslam" simulate --seed 1 --set route.laps=$laps --out d$laps
  printf "%-28s %8s (%s s of drive)\n" "  dataset" "$(du -sh d$laps | cut -f1)" "$(grep duration_s d$laps/dataset.yaml | cut -d' ' -f2)"
  peak "odometry (laps $laps)" "$parkslam" odometry d$laps --out o$laps.tum
  peak "map (laps $laps)" "$parkslam" map d$laps --out map$laps.json
  peak "eval-map (laps $laps)" "$parkslam" eval-map --map map$laps.json --truth d$laps/groundtruth/map.json
  peak "localize (laps $laps)" "$parkslam" localize --map map1.json d$laps --out loc$laps.tum --global
  peak "eval-traj (laps $laps)" "$parkslam" eval-traj --truth d$laps/groundtruth/trajectory.tum --estimate loc$laps.tum
  peak "render (laps $laps)" "$parkslam" render map$laps.json --out r$laps.svg --trajectory o$laps.tum
done
peak "follow (1 run)" "$parkslam" follow --map map1.json --runs 1 --out f1
peak "follow (4 runs)" "$parkslam" follow --map map1.json --runs 4 --out f4
peak "make-training-set (10)" "$parkslam" make-training-set --out t10 --count 10 --threads 1
peak "make-training-set (100)" "$parkslam" make-training-set --out t100 --count 100 --threads 1
peak "eval-detect --ps2 (10)" "$parkslam" eval-detect --ps2 t10
peak "eval-detect --ps2 (100)" "$parkslam" eval-detect --ps2 t100
peak "detect (one view)" "$parkslam" detect --image t10/000000.jpg
peak "report (follow, 4 runs)" "$parkslam" report f4 --out f4/report.html
