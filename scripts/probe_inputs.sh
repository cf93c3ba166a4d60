#!/usr/bin/env bash
# A hostile probe of the command line (docs/robustness.md, "The input
# probe"): corrupted variants of each input class, and outputs placed where
# they would destroy something. Every run is classed:
#   crash   exit status 128 or more (a signal), or "terminate called"
#   hang    still running after --timeout seconds
#   raw     the parser's or a library's own words reached the user
#   changed an input, or an unrelated file, is not as it was
#   litter  a temporary left behind
#   accept  an absurd input taken with exit 0
# and the probe fails if any run is. --cases N runs the first N cases (CI
# takes a few); without it, all of them.
#
#   scripts/probe_inputs.sh --parkslam build/bin/parkslam [--cases N] [--timeout S] [--verbose]
set -uo pipefail

parkslam=""
max_cases=1000000
timeout_s=60
verbose=0
while [ $# -gt 0 ]; do
  case "$1" in
    --parkslam) parkslam=$2; shift 2 ;;
    --cases) max_cases=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --verbose) verbose=1; shift ;;
    -h|--help) sed -n 2,16p "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "probe_inputs.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ -x "$parkslam" ] || { echo "probe_inputs.sh: --parkslam names no program: '$parkslam'" >&2; exit 2; }
parkslam=$(readlink -f "$parkslam")

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 2

"$parkslam" simulate --out ds --seed 3 > /dev/null 2>&1 || { echo "probe: simulate failed" >&2; exit 2; }
"$parkslam" map ds --out map.json > /dev/null 2>&1 || { echo "probe: map failed" >&2; exit 2; }
"$parkslam" make-graph --out graph.g2o --poses 200 > /dev/null 2>&1
"$parkslam" simulate --dump-config > scenario.yaml 2> /dev/null || true
"$parkslam" map --dump-config > options.yaml 2> /dev/null || true
echo keep > precious.tmp.99999999.1

runs=0
bad=0
declare -A classes

# Checksums of every file here but the outputs a case may write (out*).
snapshot() { find . -path ./out -prune -o -type f ! -name 'out*' -print0 | sort -z | xargs -0 md5sum 2> /dev/null; }

# probe CLASS-IF-EXIT-0 DESCRIPTION -- COMMAND...: one run, classed.
# CLASS-IF-EXIT-0 is "absurd" where exit 0 is wrong, "any" otherwise.
probe() {
  local kind=$1 what=$2
  shift 3
  [ $runs -lt "$max_cases" ] || return 0
  runs=$((runs + 1))
  local before after out rc verdict=""
  before=$(snapshot)
  out=$(timeout -s KILL "$timeout_s" "$@" 2>&1 < /dev/null)
  rc=$?
  after=$(snapshot)
  if [ $rc -eq 137 ]; then
    verdict=hang
  elif [ $rc -ge 128 ] || grep -q "terminate called" <<<"$out"; then
    verdict=crash
  elif grep -qE "json\.exception|yaml-cpp|filesystem error|basic_string|std::bad_alloc|what\(\)|OpenCV\(|cv::|CHOLMOD|rosbag::" <<<"$out"; then
    verdict=raw
  elif [ "$before" != "$after" ]; then
    verdict=changed
  elif [ -n "$(find . -name '*.tmp.*' ! -name precious.tmp.99999999.1 -print -quit)" ]; then
    verdict=litter
  elif [ "$kind" = absurd ] && [ $rc -eq 0 ]; then
    verdict=accept
  fi
  rm -rf out out.* 2> /dev/null
  if [ -n "$verdict" ]; then
    bad=$((bad + 1))
    classes[$verdict]=$((${classes[$verdict]:-0} + 1))
    echo "$verdict: $what (exit $rc): $(head -c 300 <<<"$out")"
  elif [ $verbose -eq 1 ]; then
    echo "ok: $what (exit $rc): $(grep -v '^ *\(reading\|mapping\|\[\)' <<<"$out" | tail -n 1 | head -c 200)"
  fi
}

edit() {  # edit SOURCE DEST SED-EXPRESSION: a corrupted copy
  cp -r "$1" "$2" && sed -i -e "$3" "$2"
}
dataset_with() {  # dataset_with NAME FILE SED-EXPRESSION: a copy of ds with one file edited
  rm -rf "$1" && cp -r ds "$1" && sed -i -e "$3" "$1/$2"
}

# Command-line numbers.
for opt in "--image-rate-hz nan" "--image-rate-hz inf" "--image-rate-hz 1e999" "--id-confusion-rate nan"; do
  probe absurd "simulate $opt" -- "$parkslam" simulate --images --out out $opt
done
probe absurd "localize --rate-hz nan" -- "$parkslam" localize ds --map map.json --out out.tum --rate-hz nan
probe absurd "make-graph --poses 200000" -- "$parkslam" make-graph --out out.g2o --poses 200000

# Outputs that would destroy something.
probe absurd "odometry --out /dev/null" -- "$parkslam" odometry ds --out /dev/null
mkfifo fifo
probe absurd "odometry --out FIFO" -- "$parkslam" odometry ds --out fifo
probe absurd "map: two outputs, one file" -- "$parkslam" map ds --out out.json --trajectory-out out.json
probe any "odometry beside a look-alike temporary" -- "$parkslam" odometry ds --out out.tum
mkdir notes && echo mine > notes/diary.txt
probe absurd "simulate --force over a folder that is not a dataset" -- "$parkslam" simulate --out notes --force

# Inputs that are not files, or never end.
probe absurd "map of a FIFO dataset file" -- bash -c "rm -rf d2 && cp -r ds d2 && rm d2/sensors/imu.csv && mkfifo d2/sensors/imu.csv && '$parkslam' map d2 --out out.json; rc=\$?; rm -rf d2; exit \$rc"
probe absurd "eval-map of /dev/zero" -- "$parkslam" eval-map --map /dev/zero --truth ds/groundtruth/map.json
probe absurd "solve-graph of /dev/zero" -- "$parkslam" solve-graph /dev/zero --out out.g2o
probe absurd "map --config /dev/zero" -- "$parkslam" map ds --out out.json --config /dev/zero

# JSON: NaN, Infinity, too large, truncated, UTF-16.
edit map.json m_nan.json '0,/\([0-9]\)\.\([0-9]\)/s//NaN/'
edit map.json m_inf.json '0,/\([0-9]\)\.\([0-9]\)/s//Infinity/'
edit map.json m_big.json '0,/\([0-9]\)\.\([0-9]\)/s//1e999/'
head -c 300 map.json > m_trunc.json
iconv -f UTF-8 -t UTF-16 map.json > m_utf16.json 2> /dev/null || printf '\xff\xfe{\0}\0' > m_utf16.json
for m in m_nan m_inf m_big m_trunc m_utf16; do
  probe absurd "eval-map $m" -- "$parkslam" eval-map --map $m.json --truth ds/groundtruth/map.json
  probe absurd "localize on $m" -- "$parkslam" localize ds --map $m.json --out out.tum
done

# YAML: NaN and huge values, unknown keys, an alias bomb.
edit options.yaml o_nan.yaml '0,/: \([0-9]*\.[0-9]*\)$/s//: .nan/'
edit options.yaml o_huge.yaml '0,/: \([0-9]*\.[0-9]*\)$/s//: 1e308/'
printf 'bogus_key: 1\n' > o_unknown.yaml
{
  echo 'a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]'
  prev=a
  for level in b c d e f g; do
    printf '%s: &%s [*%s, *%s, *%s, *%s, *%s, *%s, *%s, *%s, *%s, *%s]\n' $level $level $prev $prev $prev $prev $prev $prev $prev $prev $prev $prev
    prev=$level
  done
} > bomb.yaml
for o in o_nan o_huge o_unknown bomb; do
  probe absurd "map --config $o" -- "$parkslam" map ds --out out.json --config $o.yaml
done
probe absurd "simulate --plan bomb" -- "$parkslam" simulate --plan bomb.yaml --out out
edit scenario.yaml s_nan.yaml '0,/: \([0-9]*\.[0-9]*\)$/s//: .nan/'
probe absurd "simulate a NaN scenario" -- "$parkslam" simulate --world s_nan.yaml --out out

# Sensor CSV: NaN, out of order, absurd.
dataset_with d_nan sensors/imu.csv '3s/^\([0-9]*\),[^,]*/\1,nan/'
dataset_with d_order sensors/wheel_speed.csv '3{h;d};4G'
dataset_with d_absurd sensors/wheel_speed.csv '3s/,[^,]*$/,1e308/'
for d in d_nan d_order d_absurd; do
  probe absurd "map $d" -- "$parkslam" map $d --out out.json
  probe absurd "check-dataset $d" -- "$parkslam" check-dataset $d
done

# g2o: garbage, NaN.
edit graph.g2o g_nan.g2o '3s/ [0-9.-]* / nan /'
printf 'VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\n' > g_dangling.g2o
for g in g_nan g_dangling; do
  probe absurd "solve-graph $g" -- "$parkslam" solve-graph $g.g2o --out out.g2o
done

# Every number of the algorithm options and of the scenario, one at a time,
# at 1e308 and -1e308 (last: --cases N in CI stops before them).
for file in options scenario; do
  line_no=0
  while IFS= read -r line; do
    line_no=$((line_no + 1))
    case "$line" in
      *:\ [0-9]* | *:\ -[0-9]*) ;;
      *) continue ;;
    esac
    key=${line%%:*}
    key=${key// /}
    for huge in 1e308 -1e308; do
      sed "${line_no}s/: .*/: $huge/" $file.yaml > v.yaml
      if [ $file = options ]; then
        probe absurd "map --config: $key $huge" -- "$parkslam" map ds --out out.json --config v.yaml
      else
        probe absurd "simulate --world: $key $huge" -- "$parkslam" simulate --world v.yaml --out out
      fi
    done
  done < $file.yaml
done

echo "probe: $runs runs, $bad bad$(for c in "${!classes[@]}"; do printf ', %s %s' "${classes[$c]}" "$c"; done)"
[ "$bad" -eq 0 ]
