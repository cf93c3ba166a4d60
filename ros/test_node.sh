#!/usr/bin/env bash
# The ROS 1 node on a replayed drive (docs/ros.md): a short drive of the
# small lot is simulated with its images, written as a bag by export-rosbag,
# and played at 1x by `rosbag play --clock` to three nodes started by the
# launch file on one rosmaster: one localizing on the lot's map from the
# known start, one mapping, one updating the lot's map from the drive. `rosbag record` keeps what the localizing node
# published; its poses are scored against the truth, its rate against the
# frames `parkslam localize` tracks on the same images, the map written at
# ~save_map and at shutdown against the lot.
#
#   ros/test_node.sh BUILD_DIR
#
# Skips (77) where ROS 1's tools are not installed
# (scripts/install_deps.sh --with-ros). PARKSLAM_KEEP_TMP=1 keeps its
# folder (the bags, the nodes' logs).
set -euo pipefail
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
parkslam=$build/bin/parkslam
for tool in rosmaster roslaunch rosbag rosservice; do
  if ! command -v "$tool" > /dev/null; then
    echo "ros_node_test: $tool not found (scripts/install_deps.sh --with-ros); skipped"
    exit 77
  fi
done
[ -x "$build/ros/parkslam/parkslam_node" ] || { echo "ros_node_test: no $build/ros/parkslam/parkslam_node"; exit 1; }

tmp=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -INT "$pid" 2> /dev/null || true; done
  sleep 1
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  if [ -n "${PARKSLAM_KEEP_TMP:-}" ]; then echo "ros_node_test: kept $tmp"; else rm -rf "$tmp"; fi
}
trap cleanup EXIT
failures=0
check() {  # check "what" CONDITION...
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

# A master of this test's own, on a free port.
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOME=$tmp/ros_home
export ROS_PACKAGE_PATH=$build/ros${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}

"$parkslam" simulate --world "$here/../config/worlds/small.yaml" --seed 2 --images \
  --image-rate-hz 5 --out "$tmp/drive" > /dev/null
"$parkslam" export-rosbag "$tmp/drive" --out "$tmp/drive.bag"
truth=$tmp/drive/groundtruth
start=$(awk '!/^#/ {print $2 "," $3 "," 2 * atan2($7, $8); exit}' "$truth/trajectory.tum")
"$parkslam" localize --map "$truth/map.json" "$tmp/drive" --images --init="$start" \
  --out "$tmp/localize.tum" > "$tmp/localize.log"
tracked=$(grep -vc "^#" "$tmp/localize.tum")
echo "parkslam localize on the same images: $(head -1 "$tmp/localize.log")"

rosmaster --core -p "$port" > "$tmp/master.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
# Two roslaunch at once on a fresh master would each set a run id of their
# own, and the second to find the other's would quit.
rosparam set /run_id "parkslam-ros-node-test-$$"
launch=$here/launch/parkslam.launch
roslaunch "$launch" node_name:=localizer topics:="$tmp/drive_topics.yaml" \
  map:="$truth/map.json" init:="$start" sim_time:=true > "$tmp/localizer.log" 2>&1 &
pids+=($!)
localizer_pid=$!
roslaunch "$launch" node_name:=mapper mode:=map topics:="$tmp/drive_topics.yaml" \
  map_out:="$tmp/map.json" sim_time:=true > "$tmp/mapper.log" 2>&1 &
pids+=($!)
mapper_pid=$!
# A third updates the lot's map from the drive (mapping/map_update.h).
roslaunch "$launch" node_name:=updater mode:=map topics:="$tmp/drive_topics.yaml" \
  map:="$truth/map.json" label:=replayed map_out:="$tmp/updated.json" sim_time:=true \
  > "$tmp/updater.log" 2>&1 &
pids+=($!)
updater_pid=$!
rosbag record -O "$tmp/published.bag" /localizer/odom /localizer/state /tf /mapper/map \
  __name:=recorder \
  > "$tmp/record.log" 2>&1 &
pids+=($!)
record_pid=$!
# Both nodes up (their odometry advertised) before the drive starts.
for _ in $(seq 100); do
  topics=$(rostopic list 2> /dev/null || true)
  grep -q /localizer/odom <<< "$topics" && grep -q /mapper/odom <<< "$topics" &&
    grep -q /updater/odom <<< "$topics" && break
  sleep 0.2
done
sleep 1
# -d: the subscribers connect before the first message goes out.
rosbag play --clock -q -d 2 "$tmp/drive.bag" > "$tmp/play.log" 2>&1
sleep 2
rosservice call /mapper/save_map > "$tmp/save.log" 2>&1 || true
timeout 10 rostopic echo -n 1 /localizer/state > "$tmp/state.log" 2>&1 || true
check "~state, latched, says tracking at the end" grep -q "data: \"tracking\"" "$tmp/state.log"
check "~save_map wrote the map during the drive" grep -q "success: True" "$tmp/save.log"
kill -INT "$record_pid" "$localizer_pid" "$mapper_pid" "$updater_pid"
wait "$record_pid" "$localizer_pid" "$mapper_pid" "$updater_pid" || true
echo "localizer: $(grep -a 'frame sets' "$tmp/localizer.log" || true)"
echo "mapper:    $(grep -a 'frame sets' "$tmp/mapper.log" || true)"
echo "updater:   $(grep -a 'updated: ' "$tmp/updater.log" | tail -1 || true)"

/usr/bin/python3 "$here/scripts/odometry_to_tum.py" "$tmp/published.bag" /localizer/odom \
  "$tmp/published.tum" || true
published=$(grep -vc "^#" "$tmp/published.tum" || true)
"$parkslam" eval-traj --no-align --truth "$truth/trajectory.tum" --estimate "$tmp/published.tum" \
  | tee "$tmp/eval.log" || true
rmse=$(awk '/ATE rmse/ {print $(NF - 5)}' "$tmp/eval.log")
check "published poses' RMSE against the truth $rmse m <= 0.05 m" \
  awk -v v="$rmse" 'BEGIN {exit !(v != "" && v <= 0.05)}'
# At the camera rate: a pose at every frame set from the first fix on
# (lost or not: ~state tells), and at every frame the node tracked.
sets=$(awk -F, '$2 == "front"' "$tmp/drive/images/index.csv" | wc -l)
first_s=$(awk '!/^#/ {print $1; exit}' "$tmp/published.tum")
sets_since=$(awk -F, -v t="${first_s:-0}" '$2 == "front" && $1 / 1e9 >= t - 1e-6' \
  "$tmp/drive/images/index.csv" | wc -l)
check "a pose at $published of the $sets_since frame sets from the first fix (>= 98 %)" \
  awk -v p="$published" -v s="$sets_since" 'BEGIN {exit !(s > 0 && p >= 0.98 * s)}'
node_tracked=$(sed -n 's/.* \([0-9]*\) frames tracked.*/\1/p' "$tmp/localizer.log" | head -1)
check "of them, $node_tracked tracked (localize: $tracked)" \
  awk -v p="$published" -v t="$node_tracked" 'BEGIN {exit !(t != "" && t > 0 && p >= t)}'
check "all $sets frame sets made" grep -aq \
  "$sets frame sets (0 images in none, 0 out of order)" "$tmp/localizer.log"
# Perception keeps up: three nodes, the player and the recorder share two
# cores here (with other tests beside them in CI), so a frame set that
# waited behind a slow one may give way; at most 1 % of them.
dropped=$(sed -n 's/.* perceived, \([0-9]*\) dropped.*/\1/p' "$tmp/localizer.log" | head -1)
check "${dropped:-?} of $sets frame sets dropped (<= 1 %)" \
  awk -v d="$dropped" -v s="$sets" 'BEGIN {exit !(d != "" && d <= 0.01 * s)}'
check "the map written at shutdown" test -s "$tmp/map.json"
if [ -s "$tmp/map.json" ]; then
  "$parkslam" eval-map --map "$tmp/map.json" --truth "$truth/map.json" | tee "$tmp/map_eval.log"
  corners=$(sed -n 's/.*: observed corners \([0-9.]*\) m.*/\1/p' "$tmp/map_eval.log" | head -1)
  check "the map's observed slot corners' RMSE $corners m <= 0.1 m" \
    awk -v v="$corners" 'BEGIN {exit !(v != "" && v <= 0.1)}'
fi
# The lot's map, updated: every slot the drive passed confirmed in place.
confirmed=$(sed -n 's/.*updated: slots \([0-9]*\) confirmed, 0 moved.*/\1/p' "$tmp/updater.log" | tail -1)
check "the updater confirmed ${confirmed:-no} slots (>= 15), none moved" \
  awk -v c="$confirmed" 'BEGIN {exit !(c != "" && c >= 15)}'
check "the updated map stamped with the drive's label" \
  grep -q '"last_confirmed": "replayed"' "$tmp/updated.json"
if [ "$failures" -gt 0 ]; then
  echo "ros_node_test: $failures failed; the nodes' logs:"
  tail -n 20 "$tmp/localizer.log" "$tmp/mapper.log" "$tmp/updater.log"
  exit 1
fi
echo "ros_node_test: all passed"
