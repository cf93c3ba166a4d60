#!/usr/bin/env bash
# The parkslam command line as a user meets it: help, exit codes, messages,
# and the simulate -> odometry -> eval-traj chain on a short drive.
set -u
: "${PARKSLAM:?set PARKSLAM to the parkslam binary}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0

pass() { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL: $*"; }

# expect CODE PATTERN -- command...: exit code CODE (or "nonzero") and PATTERN in the output.
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$code" = nonzero ]; then
    [ $rc -ne 0 ] || { fail "$* exited 0, expected non-zero"; return; }
  else
    [ $rc -eq "$code" ] || { fail "$* exited $rc, expected $code: $out"; return; }
  fi
  if ! grep -qE -- "$pattern" <<<"$out"; then
    fail "$*: output lacks /$pattern/: $out"
    return
  fi
  pass
}

for cmd in simulate odometry eval-traj demo map update-map eval-map render plan-from-map localize follow topview tags detect eval-detect make-training-set report check-dataset solve-graph make-graph; do
  expect 0 "Usage|usage" -- "$PARKSLAM" "$cmd" --help
done
expect 0 "0\.1\.0" -- "$PARKSLAM" --version
expect nonzero "subcommand" -- "$PARKSLAM"
expect nonzero "--out" -- "$PARKSLAM" simulate
expect nonzero "nope.yaml" -- "$PARKSLAM" simulate --world "$tmp/nope.yaml" --out "$tmp/x"
printf 'world:\n  name: x\n  hall_size: 3\n' > "$tmp/bad.yaml"
expect nonzero "bad.yaml.*world.hall_size" -- "$PARKSLAM" simulate --world "$tmp/bad.yaml" --out "$tmp/x"
expect nonzero "sensors.ids.nope" -- "$PARKSLAM" simulate --set sensors.ids.nope=1 --out "$tmp/x"
expect nonzero "confusion" -- "$PARKSLAM" simulate --id-confusion-rate 1.5 --out "$tmp/x"
expect 0 "confusion_rate: 0.25" -- "$PARKSLAM" simulate --id-confusion-rate 0.25 --dump-config
# An empty value is refused by name, whatever the option.
expect nonzero "^--out: an empty value" -- "$PARKSLAM" simulate --out ''
expect nonzero "^--init: an empty value" -- "$PARKSLAM" odometry "$tmp/none" --out "$tmp/o.tum" --init ''
expect nonzero "^parkslam: error: --look: 'nan' is neither a look" -- "$PARKSLAM" simulate --look nan --out "$tmp/x"
[ ! -e "$tmp/x" ] && pass || fail "a refused simulate left $tmp/x"
# expect_interrupted SIGNAL AFTER_S NAME PATTERN -- command... (writing to $tmp/NAME):
# sent SIGNAL after AFTER_S seconds, it exits 128 + the signal saying PATTERN
# and leaves neither $tmp/NAME nor a staging folder beside it.
expect_interrupted() {
  local signal=$1 after_s=$2 name=$3 pattern=$4
  shift 5
  "$@" >/dev/null 2>"$tmp/signal.err" &
  local pid=$! rc
  sleep "$after_s"
  kill -"$signal" $pid
  wait $pid
  rc=$?
  local left
  left=$(ls -A "$tmp" | grep -E "^$name(\$|\.tmp)")
  if [ $rc -eq $((128 + $(kill -l "$signal"))) ] && grep -q "$pattern" "$tmp/signal.err" &&
    [ -z "$left" ]; then
    pass
  else
    fail "$* after SIG$signal: exit $rc, $(tail -1 "$tmp/signal.err"), left '$left'"
  fi
}
expect_interrupted INT 3 int "interrupted (signal 2): nothing was written to --out" -- \
  "$PARKSLAM" simulate --images --image-rate-hz 5 --out "$tmp/int"
expect_interrupted TERM 2 intdemo "interrupted (signal 15): --out is as it was" -- \
  "$PARKSLAM" demo --observations --consistency-runs 0 --follow-runs 0 --perception-frames 0 \
  --out "$tmp/intdemo"

# A short drive: approach only.
expect 0 "written to" -- "$PARKSLAM" simulate --seed 3 --set route.laps=0 --out "$tmp/d"
[ -f "$tmp/d/dataset.yaml" ] && [ -f "$tmp/d/groundtruth/trajectory.tum" ] &&
  [ -f "$tmp/d/groundtruth/map.json" ] && pass || fail "dataset files missing"
expect 0 "poses written" -- "$PARKSLAM" odometry "$tmp/d" --out "$tmp/o.tum"
expect 0 '"ate_rmse_m"' -- "$PARKSLAM" eval-traj --truth "$tmp/d/groundtruth/trajectory.tum" --estimate "$tmp/o.tum" --json
expect 0 '"length_m"' -- "$PARKSLAM" eval-traj --truth "$tmp/d/groundtruth/trajectory.tum" --estimate "$tmp/o.tum" --json
expect 0 "ATE" -- "$PARKSLAM" eval-traj --truth "$tmp/d/groundtruth/trajectory.tum" --estimate "$tmp/o.tum"

# Mapping the short drive, evaluating and drawing the map.
expect 0 "map written" -- "$PARKSLAM" map "$tmp/d" --out "$tmp/m.json" --trajectory-out "$tmp/mt.tum"
expect 0 '"slot_corner_rmse_m"' -- "$PARKSLAM" eval-map --map "$tmp/m.json" --truth "$tmp/d/groundtruth/map.json" --json
expect 0 '"slots_duplicate"' -- "$PARKSLAM" eval-map --map "$tmp/m.json" --truth "$tmp/d/groundtruth/map.json" --json
expect 0 "wrote" -- "$PARKSLAM" render "$tmp/m.json" --out "$tmp/m.svg" --trajectory "$tmp/mt.tum"
grep -q "</svg>" "$tmp/m.svg" && pass || fail "render wrote no SVG"
expect 0 "map written" -- "$PARKSLAM" map "$tmp/d" --out "$tmp/m2.json" --robust none --mode online
# The online map along the drive, scored every 5 s against the truth.
expect 0 "along the drive .*slots seen twice: observed corners at worst" -- "$PARKSLAM" map "$tmp/d" \
  --out "$tmp/m4.json" --mode online --track-out "$tmp/track.csv" --track-every-s 5 --track-batch
head -1 "$tmp/track.csv" | grep -q "^t_s,slots_matched,.*,batch_tag_rmse_m$" && pass || fail "track.csv header"
[ "$(wc -l < "$tmp/track.csv")" -ge 5 ] && pass || fail "track.csv has too few rows"
expect nonzero "track-every-s" -- "$PARKSLAM" map "$tmp/d" --out "$tmp/m5.json" --track-out "$tmp/t.csv" --track-every-s 0
expect nonzero "robust" -- "$PARKSLAM" map "$tmp/d" --out "$tmp/m3.json" --robust maybe
printf '{"format": "parkslam-map", "version": 2}' > "$tmp/badmap.json"
expect nonzero "badmap.json.*version" -- "$PARKSLAM" eval-map --map "$tmp/badmap.json" --truth "$tmp/d/groundtruth/map.json"
printf '{"format": "parkslam-map", ' > "$tmp/truncated.json"
expect nonzero "truncated.json" -- "$PARKSLAM" render "$tmp/truncated.json" --out "$tmp/x.svg"
[ ! -e "$tmp/x.svg" ] && pass || fail "a failed render left an output file"
# A number beyond a double is refused by the JSON parser without a position.
printf '{"format": "parkslam-map", "version": 1, "frame": "map", "units": {"length": "m", "angle": "rad"}, "metadata": {}, "slots": [], "tags": [{"id": 7, "x": 1e999, "y": 0, "yaw": 0, "size_m": 0.488, "obstacle": -1}], "obstacles": []}' > "$tmp/overflow.json"
expect nonzero "overflow.json: tags\[0\]\.x: invalid JSON.*1e999" -- "$PARKSLAM" eval-map --map "$tmp/overflow.json" --truth "$tmp/d/groundtruth/map.json"
# A finite number beyond its plausible range (docs/plausible_ranges.md).
sed '0,/"corners": \[\[[^,]*/s//"corners": [[1e308/' "$tmp/m.json" > "$tmp/far.json"
expect nonzero 'far.json: slots\[0\]\.corners\[0\]\[0\]: 1e\+308 is beyond the plausible 100000 m' -- "$PARKSLAM" render "$tmp/far.json" --out "$tmp/far.svg"

# Localizing on the map and following the trace in closed loop.
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --global
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --init 0,0,0
# What the landmarks taught of the wheel, and nothing where it is not estimated.
expect 0 "wheel speed reads [+-][0-9.]+ % \(sigma [0-9.]+ %\)" -- "$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --init 0,0,0
printf 'localizer:\n  estimate_wheel_scale: false\n' > "$tmp/noscale.yaml"
out=$("$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --init 0,0,0 --config "$tmp/noscale.yaml" 2>&1)
grep -q "wheel speed reads" <<<"$out" && fail "localize with estimate_wheel_scale false still speaks of the wheel" || pass
expect nonzero "excludes|--global" -- "$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --init 0,0,0 --global
# The mapper's map keeps where its drive began; the ground truth has no entrance.
grep -q '"entrance"' "$tmp/m.json" && pass || fail "the mapper's map has no entrance"
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/m.json" "$tmp/d" --out "$tmp/l.tum" --init entrance
expect nonzero "--init entrance: .*map.json has no entrance" -- "$PARKSLAM" localize --map "$tmp/d/groundtruth/map.json" "$tmp/d" --out "$tmp/l2.tum" --init entrance
expect nonzero "badmap.json" -- "$PARKSLAM" localize --map "$tmp/badmap.json" "$tmp/d" --out "$tmp/l2.tum"
expect nonzero "overflow.json: tags\[0\]\.x: invalid JSON" -- "$PARKSLAM" localize --map "$tmp/overflow.json" "$tmp/d" --out "$tmp/l2.tum"
expect 0 '"repeat_std_m"' -- "$PARKSLAM" follow --map "$tmp/m.json" --runs 2 --speed-kmh 10 --set route.laps=0 --out "$tmp/f" --json
[ -f "$tmp/f/run_01.tum" ] && [ -f "$tmp/f/traces.svg" ] && pass || fail "follow outputs missing"
printf '0 0 0 0 0 0 0 1\n1 nan 0 0 0 0 0 1\n' > "$tmp/nan.tum"
expect nonzero "nan.tum:2" -- "$PARKSLAM" follow --map "$tmp/m.json" --runs 1 --trace "$tmp/nan.tum" --out "$tmp/f2"
printf '{"format": "parkslam-map", "version": 1, "frame": "map", "units": {"length": "m", "angle": "rad"}, "metadata": {}, "slots": [], "tags": [], "obstacles": []}' > "$tmp/empty.json"
expect nonzero "fewer than 3 slots" -- "$PARKSLAM" follow --map "$tmp/empty.json" --runs 1 --out "$tmp/f3"

# Rendered images and their top view.
expect 0 "written to" -- "$PARKSLAM" simulate --seed 4 --set route.laps=0 --set route.finish_m=[] --images --image-rate-hz 0.2 --out "$tmp/img"
[ -f "$tmp/img/images/index.csv" ] && [ -f "$tmp/img/images/rig.yaml" ] && [ -f "$tmp/img/images/front_mono/0.jpg" ] && pass || fail "image files missing"
expect 0 "600x600" -- "$PARKSLAM" topview --rig "$tmp/img/images/rig.yaml" --front "$tmp/img/images/front/0.jpg" --rear "$tmp/img/images/rear/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top.png"
expect 0 "600x600" -- "$PARKSLAM" topview --rig "$tmp/img/images/rig.yaml" --seams footprint_rays --front "$tmp/img/images/front/0.jpg" --rear "$tmp/img/images/rear/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top_rays.png"
expect 1 "" -- cmp -s "$tmp/top.png" "$tmp/top_rays.png"
expect nonzero "seams.*curved" -- "$PARKSLAM" topview --seams curved --front "$tmp/img/images/front/0.jpg" --rear "$tmp/img/images/rear/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top5.png"
expect nonzero "nope.jpg: no such file" -- "$PARKSLAM" topview --front "$tmp/nope.jpg" --rear "$tmp/img/images/rear/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top2.png"
expect nonzero "'rear'.*640x480" -- "$PARKSLAM" topview --front "$tmp/img/images/front/0.jpg" --rear "$tmp/img/images/front_mono/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top3.png"
printf 'cameras:\n  - name: front\n    modle: fisheye\n' > "$tmp/badrig.yaml"
expect nonzero "badrig.yaml.*cameras\[0\]" -- "$PARKSLAM" topview --rig "$tmp/badrig.yaml" --front "$tmp/img/images/front/0.jpg" --rear "$tmp/img/images/rear/0.jpg" --left "$tmp/img/images/left/0.jpg" --right "$tmp/img/images/right/0.jpg" --out "$tmp/top4.png"

# Tags in a rendered front-camera image (the corridor start sees tags).
expect 0 '"tags":\[\{"alpha_rad"' -- "$PARKSLAM" tags --image "$tmp/img/images/front_mono/0.jpg" --json
expect nonzero "image is 640x480" -- "$PARKSLAM" tags --image "$tmp/img/images/front/0.jpg"
expect nonzero "no camera 'roof'" -- "$PARKSLAM" tags --image "$tmp/img/images/front_mono/0.jpg" --camera "$tmp/img/images/rig.yaml" --camera-name roof

# Slots in a top view: JSON with the issue's keys, an overlay, clear errors.
expect 0 '^\{"marking_points":\[.*\],"slots":\[' -- "$PARKSLAM" detect --image "$tmp/top.png" --json
expect 0 "wrote $tmp/overlay.png" -- "$PARKSLAM" detect --image "$tmp/top.png" --out "$tmp/overlay.png"
# The learned detector on the same view (the corridor: nothing to find), on
# a real ps2.0 view where a car parks in the middle one of three slots
# (skipped without ../shared/data), and its scale and files.
expect 0 '^\{"marking_points":\[.*\],"slots":\[' -- "$PARKSLAM" detect --image "$tmp/top.png" --detector learned --json
sample="${PARKSLAM_SHARED_DATA:-$(dirname "$0")/../../../shared/data}/ps2.0-sample/20160816-1-1540.jpg"
if [ -f "$sample" ]; then
  expect 0 "^4 marking points, 3 slots" -- "$PARKSLAM" detect --image "$sample" --detector learned --no-ids
  # The learned detector is the default; the classical one pairs none there.
  expect 0 "^4 marking points, 3 slots" -- "$PARKSLAM" detect --image "$sample" --no-ids
  expect 0 "^4 marking points, 0 slots" -- "$PARKSLAM" detect --image "$sample" --detector classical --no-ids
else
  echo "skipped: real ps2.0 view not found at $sample"
fi
expect nonzero "needs 60 .*got 50; --detector classical takes any scale" -- "$PARKSLAM" detect --image "$tmp/top.png" --pixels-per-m 50
expect 0 '"slots":' -- "$PARKSLAM" detect --image "$tmp/top.png" --detector classical --pixels-per-m 50 --json
expect nonzero "nomodels/marking_points.onnx: no such weights file" -- "$PARKSLAM" detect --image "$tmp/top.png" --detector learned --models "$tmp/nomodels"
[ -s "$tmp/overlay.png" ] && pass || fail "no overlay written"
expect nonzero "nope.png: no such file" -- "$PARKSLAM" detect --image "$tmp/nope.png"
printf 'not an image' > "$tmp/fake.png"
expect nonzero "fake.png: not a PNG, JPEG, BMP or binary PNM image" -- "$PARKSLAM" detect --image "$tmp/fake.png"
expect 0 '"slots":\{"false_negatives"' -- "$PARKSLAM" eval-detect --seed 4 --set route.laps=0 --max-frames 3 --rate-hz 0.1 --json
expect nonzero "no labelled ps2.0 images" -- "$PARKSLAM" eval-detect --ps2 "$tmp"

# On the dataset's own images.
expect 0 "map written" -- "$PARKSLAM" map "$tmp/img" --out "$tmp/rec_map.json" --images
expect nonzero "images/index.csv: missing" -- "$PARKSLAM" map "$tmp/d" --out "$tmp/rec_map2.json" --images
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/rec_map.json" "$tmp/img" --out "$tmp/rec.tum" --images --init 0,0,0

# Live cameras: rendered on the fly into the stream, nothing written.
expect 0 "map written" -- "$PARKSLAM" map "$tmp/img" --out "$tmp/live_map.json" --live-images 1
[ ! -e "$tmp/img/images/front/1000000000.jpg" ] && pass || fail "live images were written"
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/live_map.json" "$tmp/img" --out "$tmp/live.tum" --live-images 1 --init 0,0,0
expect 0 '"repeat_std_m"' -- "$PARKSLAM" follow --map "$tmp/m.json" --runs 1 --speed-kmh 10 --set route.laps=0 --live-images 0.5 --out "$tmp/fl" --json

# Bad inputs name the file and what is wrong.
expect nonzero "missing|dataset.yaml" -- "$PARKSLAM" odometry "$tmp/none" --out "$tmp/o2.tum"
expect nonzero "init" -- "$PARKSLAM" odometry "$tmp/d" --out "$tmp/o2.tum" --init 1,2
expect nonzero "--init: x 1e\+308 is beyond the plausible 100000 m" -- "$PARKSLAM" odometry "$tmp/d" --out "$tmp/o2.tum" --init 1e308,2,0
printf '0 0 0 0 0 0 0 1\n1 nan 0 0 0 0 0 1\n' > "$tmp/nan.tum"
expect nonzero "nan.tum:2" -- "$PARKSLAM" eval-traj --truth "$tmp/nan.tum" --estimate "$tmp/o.tum"
printf '0 0 0 0 0 0 0 1\n0 1 0 0 0 0 0 1\n' > "$tmp/order.tum"
expect nonzero "order.tum:2" -- "$PARKSLAM" eval-traj --truth "$tmp/order.tum" --estimate "$tmp/o.tum"
cp -r "$tmp/d" "$tmp/corrupt"
sed -i '5s/.*/123,abc/' "$tmp/corrupt/sensors/wheel_speed.csv"
expect nonzero "wheel_speed.csv:5" -- "$PARKSLAM" odometry "$tmp/corrupt" --out "$tmp/o3.tum"
[ ! -e "$tmp/o3.tum" ] && pass || fail "a failed odometry run left an output file"
cp -r "$tmp/d" "$tmp/overflow"
sed -i '0,/"sigma_m":[^,]*/s//"sigma_m":1e999/' "$tmp/overflow/observations/slots.jsonl"
expect nonzero 'slots.jsonl:[0-9]+: slots\[[0-9]+\]\.sigma_m: invalid JSON' -- "$PARKSLAM" odometry "$tmp/overflow" --out "$tmp/o4.tum"

# Randomized training views: labelled in the ps2.0 form that eval-detect reads,
# deterministic by seed, and a folder with files in it is not overwritten.
expect 0 "3 top views" -- "$PARKSLAM" make-training-set --out "$tmp/ts" --count 3 --seed 5 --threads 1
[ -f "$tmp/ts/000002.jpg" ] && [ -f "$tmp/ts/000002.json" ] && [ -f "$tmp/ts/manifest.json" ] && pass ||
  fail "make-training-set did not write its images, labels and manifest"
expect 0 "3 images" -- "$PARKSLAM" eval-detect --ps2 "$tmp/ts"
expect 0 "3 top views" -- "$PARKSLAM" make-training-set --out "$tmp/ts2" --count 3 --seed 5 --threads 2
cmp -s "$tmp/ts/000001.jpg" "$tmp/ts2/000001.jpg" && cmp -s "$tmp/ts/000001.json" "$tmp/ts2/000001.json" && pass ||
  fail "make-training-set is not deterministic by seed across thread counts"
expect nonzero "not empty" -- "$PARKSLAM" make-training-set --out "$tmp/ts" --count 1
expect nonzero "--kind" -- "$PARKSLAM" make-training-set --out "$tmp/ts3" --count 1 --kind faces
expect nonzero "--fonts: $tmp/nofonts: not a folder" -- "$PARKSLAM" make-training-set --out "$tmp/ts4" --count 1 --fonts "$tmp/nofonts"
# The fonts folder under another path renders the same scene.
if [ -d /usr/share/fonts ]; then
  mkdir -p "$tmp/fontcopy" && ln -s /usr/share/fonts "$tmp/fontcopy/fonts"
  expect 0 "1 top views" -- "$PARKSLAM" make-training-set --out "$tmp/ts5" --count 1 --seed 5 --fonts "$tmp/fontcopy/fonts"
  cmp -s "$tmp/ts/000000.jpg" "$tmp/ts5/000000.jpg" && pass || fail "make-training-set --fonts COPY renders another scene"
fi
expect 0 "ID crops" -- "$PARKSLAM" make-training-set --out "$tmp/ids" --count 6 --seed 3 --kind ids
head -1 "$tmp/ids/ids/labels.csv" | grep -q "^file,text$" && pass || fail "ids/labels.csv lacks its header"

# check-dataset: a good dataset with images, then each problem named by its file.
"$PARKSLAM" simulate --world "$(dirname "$0")/../../config/worlds/small.yaml" --seed 2 --images \
  --image-rate-hz 1 --out "$tmp/cd" > /dev/null 2>&1
expect 0 "cd: ok" -- "$PARKSLAM" check-dataset "$tmp/cd"
cp -r "$tmp/cd" "$tmp/cd_missing" && rm "$tmp/cd_missing/sensors/imu.csv"
expect nonzero "imu.csv" -- "$PARKSLAM" check-dataset "$tmp/cd_missing"
cp -r "$tmp/cd" "$tmp/cd_backwards" && sed -i '10{h;d};11G' "$tmp/cd_backwards/sensors/wheel_speed.csv"
expect nonzero "wheel_speed.csv:11" -- "$PARKSLAM" check-dataset "$tmp/cd_backwards"
cp -r "$tmp/cd" "$tmp/cd_size"
first_front=$(ls "$tmp/cd_size/images/front" | head -1)
cp "$tmp/cd_size/images/front_mono/$first_front" "$tmp/cd_size/images/front/$first_front"
expect nonzero "front/$first_front: 1280 x 720 pixels, but images/rig.yaml gives camera 'front' 640 x 480" -- \
  "$PARKSLAM" check-dataset "$tmp/cd_size"
cp -r "$tmp/cd" "$tmp/cd_gap" && sed -i '100,115d' "$tmp/cd_gap/observations/slots.jsonl"
expect nonzero "slots.jsonl: a gap of 1.70 s" -- "$PARKSLAM" check-dataset "$tmp/cd_gap"
expect nonzero "not a folder" -- "$PARKSLAM" check-dataset "$tmp/nothing_here"

# A recording from a real car has no scenario: it is checked, mapped and
# localized (on its recorded images) all the same; live rendering needs a world.
cp -r "$tmp/cd" "$tmp/real" && sed -i '/^scenario:/,$d' "$tmp/real/dataset.yaml"
grep -q "^scenario:" "$tmp/real/dataset.yaml" && fail "the scenario was not removed" || pass
expect 0 "real: ok" -- "$PARKSLAM" check-dataset "$tmp/real"
expect 0 "map written" -- "$PARKSLAM" map "$tmp/real" --images --out "$tmp/real_map.json"
expect 0 "slot corner RMSE 0\.0[0-4]" -- "$PARKSLAM" eval-map --map "$tmp/real_map.json" \
  --truth "$tmp/real/groundtruth/map.json"
expect 0 "poses written" -- "$PARKSLAM" localize --map "$tmp/real_map.json" "$tmp/real" --images \
  --out "$tmp/real_loc.tum"
expect 0 "ATE rmse / mean / max 0\.0[0-4]" -- "$PARKSLAM" eval-traj \
  --truth "$tmp/real/groundtruth/trajectory.tum" --estimate "$tmp/real_loc.tum"
expect nonzero "no scenario" -- "$PARKSLAM" map "$tmp/real" --live-images 1 --out "$tmp/x.json"

# ROS 1 bags: the recording written as a car's recorder would, read back, and
# mapped to the very same map.
if "$PARKSLAM" import-rosbag --help > /dev/null 2>&1; then
  expect 0 "wrote .*real.bag" -- "$PARKSLAM" export-rosbag "$tmp/real" --out "$tmp/real.bag"
  expect 0 "frame sets of images \(0 images in no complete set" -- \
    "$PARKSLAM" import-rosbag "$tmp/real.bag" --topics "$tmp/real_topics.yaml" --out "$tmp/from_bag"
  expect 0 "from_bag: ok" -- "$PARKSLAM" check-dataset "$tmp/from_bag"
  expect 0 "map written" -- "$PARKSLAM" map "$tmp/from_bag" --images --out "$tmp/bag_map.json"
  cmp -s "$tmp/bag_map.json" "$tmp/real_map.json" && pass || fail "the map from the bag differs"
  expect nonzero "not empty" -- "$PARKSLAM" import-rosbag "$tmp/real.bag" \
    --topics "$tmp/real_topics.yaml" --out "$tmp/from_bag"
  sed -i 's#/imu/data#/imu/nope#' "$tmp/real_topics.yaml"
  expect nonzero "real.bag: imu: topic /imu/nope is not in the bag" -- "$PARKSLAM" import-rosbag \
    "$tmp/real.bag" --topics "$tmp/real_topics.yaml" --out "$tmp/from_bag2"
  # A failed import does not say it read the whole bag.
  "$PARKSLAM" import-rosbag "$tmp/real.bag" --topics "$tmp/real_topics.yaml" \
    --out "$tmp/from_bag2" 2>&1 | grep -q "100%" && fail "a failed import drew a full bar" || pass
else
  echo "cli_test: built without rosbag_storage, import-rosbag not tested"
fi

# update-map: the small lot mapped, then changed (slots moved and
# repainted, tags moved, one taken down) and driven again.
small="$(dirname "$0")/../../config/worlds/small.yaml"
changes="--set world.changes.seed=1 --set world.changes.moved_slot_share=0.1
  --set world.changes.repainted_slot_share=0.1 --set world.changes.moved_tags=2
  --set world.changes.removed_tags=1"
"$PARKSLAM" simulate --world "$small" --seed 2 --out "$tmp/u1" > /dev/null 2>&1
# shellcheck disable=SC2086
"$PARKSLAM" simulate --world "$small" --seed 3 $changes --out "$tmp/u2" > /dev/null 2>&1
"$PARKSLAM" map "$tmp/u1" --out "$tmp/u1_map.json" > /dev/null 2>&1
expect 0 "slots: 18 confirmed, 2 moved, 2 repainted, 0 added" -- "$PARKSLAM" update-map \
  --map "$tmp/u1_map.json" "$tmp/u2" --out "$tmp/u_map.json" --label second-drive
expect 0 "0 duplicate" -- "$PARKSLAM" eval-map --map "$tmp/u_map.json" --truth "$tmp/u2/groundtruth/map.json"
expect 0 "observed corners 0\.0[0-4][0-9] m" -- "$PARKSLAM" eval-map --map "$tmp/u_map.json" \
  --truth "$tmp/u2/groundtruth/map.json"
grep -q '"last_confirmed": "second-drive"' "$tmp/u_map.json" && pass || fail "update-map stamped nothing"
expect nonzero "agree on where the new drive" -- "$PARKSLAM" update-map --map "$tmp/u1_map.json" \
  "$tmp/d" --out "$tmp/u_bad.json"
expect nonzero "changes.moved_slot_share" -- "$PARKSLAM" simulate --set world.changes.moved_slot_share=2 \
  --out "$tmp/x"

# --config and --dump-config: the algorithm options from one file.
expect 0 "^mapper:" -- "$PARKSLAM" map --dump-config
expect 0 "^follower:" -- "$PARKSLAM" follow --dump-config
"$PARKSLAM" localize --dump-config > "$tmp/options.yaml"
expect 0 "map written" -- "$PARKSLAM" map "$tmp/cd" --config "$tmp/options.yaml" --out "$tmp/cfg_map.json"
expect 0 "map written" -- "$PARKSLAM" map "$tmp/cd" --config "$(dirname "$0")/../../config/options.yaml" \
  --out "$tmp/cfg_map2.json"
printf 'localizer:\n  nn_radius: 2\n' > "$tmp/typo.yaml"
expect nonzero "typo.yaml:2: localizer.nn_radius: unknown key \(did you mean 'nn_radius_m'\?\)" -- \
  "$PARKSLAM" localize --map "$tmp/cfg_map.json" "$tmp/cd" --config "$tmp/typo.yaml" --out "$tmp/t.tum"
[ ! -e "$tmp/t.tum" ] && pass || fail "localize wrote an output despite a bad --config"

# make-graph and solve-graph: a ring with outliers, solved plainly and with Max-Mixture.
expect nonzero "would give the graph 1000[0-9]* edges; solve-graph takes at most 200000" -- \
  "$PARKSLAM" make-graph --poses 100 --outliers 1000000 --out "$tmp/huge.g2o"
[ ! -e "$tmp/huge.g2o" ] && pass || fail "make-graph wrote a graph over the limit"
expect 0 "300 poses.*20 random" -- "$PARKSLAM" make-graph --world ring --poses 300 --outliers 20 \
  --seed 4 --out "$tmp/ring.g2o" --truth "$tmp/ring_truth.g2o"
expect 0 "Max-Mixture: 2[0-9] of" -- "$PARKSLAM" solve-graph "$tmp/ring.g2o" --robust maxmix \
  --truth "$tmp/ring_truth.g2o" --out "$tmp/ring_mm.g2o"
mm_rmse=$("$PARKSLAM" solve-graph "$tmp/ring.g2o" --robust maxmix --json --out "$tmp/ring_mm.g2o" \
  --truth "$tmp/ring_truth.g2o" | sed 's/.*"rmse_m":\([0-9.e-]*\).*/\1/')
plain_rmse=$("$PARKSLAM" solve-graph "$tmp/ring.g2o" --json --out "$tmp/ring_plain.g2o" \
  --truth "$tmp/ring_truth.g2o" | sed 's/.*"rmse_m":\([0-9.e-]*\).*/\1/')
awk -v m="$mm_rmse" -v p="$plain_rmse" 'BEGIN { exit !(m < 0.5 && p > 5 * m) }' && pass ||
  fail "solve-graph: Max-Mixture RMSE $mm_rmse m against plain $plain_rmse m"
grep -c "^VERTEX_SE2" "$tmp/ring_mm.g2o" | grep -qx 300 && pass || fail "solve-graph wrote no 300 vertices"
expect nonzero "ring.g2o: lies|input FILE" -- "$PARKSLAM" solve-graph "$tmp/ring.g2o" --out "$tmp/ring.g2o"
printf 'VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n' > "$tmp/bad.g2o"
expect nonzero "bad.g2o:2: EDGE_SE2.to: no VERTEX_SE2 1" -- "$PARKSLAM" solve-graph "$tmp/bad.g2o" --out "$tmp/o.g2o"
[ ! -e "$tmp/o.g2o" ] && pass || fail "solve-graph wrote an output for a bad input"
# The ring (its 20 random outliers last) spoiled with 15 local ones more;
# the 35 wrong ones counted by --wrong-last.
expect 0 "300 poses.*0 random, 15 local" -- "$PARKSLAM" make-graph --base "$tmp/ring_plain.g2o" \
  --base-truth "$tmp/ring_truth.g2o" --local 15 --out "$tmp/ring_local.g2o"
expect nonzero "--local and --groups need --base-truth" -- "$PARKSLAM" make-graph \
  --base "$tmp/ring_plain.g2o" --local 15 --out "$tmp/o.g2o"
expect 0 "of the last 35 closures \(wrong\): 0 kept; true closures rejected: 0" -- \
  "$PARKSLAM" solve-graph "$tmp/ring_local.g2o" --robust maxmix --wrong-last 35 --out "$tmp/o.g2o"
expect nonzero "--wrong-last 100000 exceeds the" -- "$PARKSLAM" solve-graph "$tmp/ring_local.g2o" \
  --wrong-last 100000 --out "$tmp/o.g2o"
# A Max-Mixture file's own null hypothesis is the default.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nEDGE_SE2 0 1 1 0 0 100 0 0 100 0 100\nEDGE_SE2 1 2 1 0 0 100 0 0 100 0 100\nEDGE_SE2_MIXTURE 0 2 2 EDGE_SE2 1 0 2 2 0 0 100 0 0 100 0 100 EDGE_SE2 0.1 0 2 2 0 0 1e-4 0 0 1e-4 0 1e-4\n' > "$tmp/mix.g2o"
expect 0 "null weight 0.1, information scale 1e-06, the file's" -- "$PARKSLAM" solve-graph \
  "$tmp/mix.g2o" --robust maxmix --out "$tmp/mix_out.g2o"

# report: a demo folder, then broken inputs named by file, line and column.
"$PARKSLAM" demo --out "$tmp/rep" --observations --consistency-runs 2 --follow-runs 1 \
  --perception-frames 2 --world "$(dirname "$0")/../../config/worlds/small.yaml" > "$tmp/rep.log" 2>&1
grep -qE "wheel speed reads [+-][0-9.]+ % \(sigma [0-9.]+ %\)" "$tmp/rep.log" \
  && grep -q '"wheel_scale_sigma"' "$tmp/rep/metrics.json" && pass \
  || fail "demo does not say what the localizer learnt of the wheel"
grep -q '"mean_turning_nees"' "$tmp/rep/metrics.json" && [ "$(grep -c '"window_s"' "$tmp/rep/metrics.json")" -eq 2 ] \
  && pass || fail "metrics.json lacks the dead reckoning's 1 s and 5 s window consistency"
expect 0 "wrote .*again.html" -- "$PARKSLAM" report "$tmp/rep" --out "$tmp/rep/again.html"
sed -i '5s/^[^,]*,/abc,/' "$tmp/rep/localization.csv"
expect nonzero "localization.csv:5: t_s: not a number 'abc'" -- "$PARKSLAM" report "$tmp/rep" --out "$tmp/rep/bad.html"
[ ! -e "$tmp/rep/bad.html" ] && pass || fail "report left a page behind after an error"
echo "{" > "$tmp/rep/metrics.json"
expect nonzero "metrics.json: invalid JSON: at line 2, column 1: ends before its value does" -- "$PARKSLAM" report "$tmp/rep"
expect nonzero "nothing to report" -- "$PARKSLAM" report "$tmp"
expect nonzero "nope: not a folder" -- "$PARKSLAM" report "$tmp/nope"

# Outputs never replace inputs, by any name; simulate keeps a full folder.
"$PARKSLAM" simulate --out "$tmp/g" --world "$(dirname "$0")/../../config/worlds/small.yaml" > /dev/null 2>&1
expect nonzero "not empty.*--force" -- "$PARKSLAM" simulate --out "$tmp/g"
expect nonzero "lies inside the input DIR" -- "$PARKSLAM" odometry "$tmp/g" --out "$tmp/g/sensors/wheel_speed.csv"
expect nonzero "lies inside the input DIR" -- "$PARKSLAM" map "$tmp/g" --out "$tmp/g/dataset.yaml"
"$PARKSLAM" map "$tmp/g" --out "$tmp/gm.json" > /dev/null 2>&1
expect nonzero "is the input MAP" -- "$PARKSLAM" render "$tmp/gm.json" --out "$tmp/new/../gm.json"
expect nonzero "is the input --map" -- "$PARKSLAM" localize "$tmp/g" --map "$tmp/gm.json" --out "$tmp/gm.json"
expect nonzero "is the input DIR" -- "$PARKSLAM" report "$tmp/rep" --out "$tmp/rep/map.json"
head -c 1 "$tmp/gm.json" | grep -q "{" && pass || fail "the refused commands changed the map"
expect 0 "written to" -- "$PARKSLAM" simulate --out "$tmp/g" --force --world "$(dirname "$0")/../../config/worlds/small.yaml"

# Images: the size is read from the header before decoding; tiny ones are named.
printf '\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x4e\x20\x00\x00\x4e\x20\x08\x00\x00\x00\x00' > "$tmp/huge.png"
expect nonzero "huge.png: an image of 20000 x 20000 pixels" -- "$PARKSLAM" detect --image "$tmp/huge.png"
expect nonzero "huge.png: an image of 20000 x 20000 pixels" -- "$PARKSLAM" tags --image "$tmp/huge.png"
printf '\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01\x08\x00\x00\x00\x00\x3a\x7e\x9b\x55\x00\x00\x00\x0a\x49\x44\x41\x54\x78\x9c\x63\x60\x00\x00\x00\x02\x00\x01\x48\xaf\xa4\x71\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82' > "$tmp/one.png"
expect nonzero "one.png: an image of 1 x 1 pixels; a top view needs at least 64 x 64" -- "$PARKSLAM" detect --image "$tmp/one.png"

expect nonzero "initial-trust-region.*1e-32 to 1e16" -- "$PARKSLAM" map "$tmp/g" --out "$tmp/tr.json" --initial-trust-region 1e300

# A world from a plan (docs/world_plan.md): the example garage simulated,
# mapped and scored; a map turned back into a plan; plans refused with the
# file and the key.
plan="$(dirname "$0")/../../config/plans/example_garage.yaml"
expect 0 "example_garage-seed1: 104.0 s, 146.4 m driven" -- "$PARKSLAM" simulate --plan "$plan" --out "$tmp/pl"
expect 0 "map written" -- "$PARKSLAM" map "$tmp/pl" --out "$tmp/pl_map.json"
expect 0 "slots: 28 of 28 matched" -- "$PARKSLAM" eval-map --map "$tmp/pl_map.json" --truth "$tmp/pl/groundtruth/map.json"
expect 0 "plan of 28 slots, 12 tags, 5 walls, 3 pillars, [0-9]+ waypoints" -- "$PARKSLAM" plan-from-map "$tmp/pl/groundtruth/map.json" --route "$tmp/pl/groundtruth/trajectory.tum" --out "$tmp/pl_again.yaml"
expect 0 "written to" -- "$PARKSLAM" simulate --plan "$tmp/pl_again.yaml" --out "$tmp/pl2"
expect 0 "its route is empty" -- "$PARKSLAM" plan-from-map "$tmp/pl_map.json" --out "$tmp/pl_mapped.yaml"
expect nonzero "pl_mapped.yaml: route: needs at least two waypoints" -- "$PARKSLAM" simulate --plan "$tmp/pl_mapped.yaml" --out "$tmp/x"
sed 's/corners_m/corner_m/' "$plan" > "$tmp/bad_plan.yaml"
expect nonzero "bad_plan.yaml:[0-9]+: slots\[0\].corner_m: unknown key" -- "$PARKSLAM" simulate --plan "$tmp/bad_plan.yaml" --out "$tmp/x"
expect nonzero "excludes" -- "$PARKSLAM" simulate --plan "$plan" --world default --out "$tmp/x"
# The built-in lot as a plan drives the same drive.
"$PARKSLAM" simulate --dump-plan > "$tmp/default_plan.yaml"
expect 0 "default-seed1: 327.6 s, 596.3 m driven.*9591 slots.*3613 tags" -- "$PARKSLAM" simulate --plan "$tmp/default_plan.yaml" --out "$tmp/dp"

# Seeds are whole numbers in range, never wrapped around.
expect nonzero "a seed is a whole number.*'-1'" -- "$PARKSLAM" simulate --seed -1 --out "$tmp/s1"
expect nonzero "a seed is a whole number.*'-1'" -- "$PARKSLAM" make-training-set --seed -1 --count 1 --out "$tmp/ts_neg"
expect nonzero "a seed is a whole number.*'18446744073709551616'" -- "$PARKSLAM" simulate --seed 18446744073709551616 --out "$tmp/s1"
expect nonzero "a seed is a whole number" -- "$PARKSLAM" demo --seed 1.5 --out "$tmp/s1"
[ ! -e "$tmp/s1" ] && pass || fail "a refused seed left a folder"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
