#!/usr/bin/env bash
# Builds the libFuzzer targets of every input parser (fuzz/, with Clang,
# AddressSanitizer and UndefinedBehaviorSanitizer) in build-fuzz/ and runs
# each for a while; docs/robustness.md explains the targets and the table.
#
#   scripts/fuzz.sh [--seconds N] [--parallel P] [--coverage] [TARGET...]
#
# --seconds N   how long each target runs (default 600)
# --parallel P  how many targets run at once (default: the number of cores)
# --coverage    also builds build-fuzz-cov/ (Clang's source-based coverage)
#               and reports the lines of each parser's own sources that the
#               corpus runs
# TARGET        fuzz_tum, fuzz_map_json, ... (default: all of them)
#
# Corpora grow in build-fuzz/corpus/<target>/, seeded from what the project
# writes (fuzz_seeds) and its shipped config files, and are kept for the next
# run. A crash, a hang (10 s), more than 2 GB of memory, an exception other
# than the parsers' IoError, or a rejection that does not name its file is a
# finding: its input is saved as build-fuzz/findings/<target>-*, and the
# script exits 1. Prints per target: executions, executions per second, the
# edges covered (libFuzzer's cov, over everything linked) and the corpus.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=600
parallel=$(nproc)
coverage=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a number}; shift 2 ;;
    --parallel) parallel=${2:?--parallel needs a number}; shift 2 ;;
    --coverage) coverage=1; shift ;;
    -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
case "$seconds$parallel" in
  *[!0-9]*) echo "fuzz.sh: --seconds and --parallel take whole numbers" >&2; exit 2 ;;
esac

scripts/install_deps.sh --with-fuzzer
source scripts/compiler_cache.sh
CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPARKSLAM_FUZZ=ON \
  -DPARKSLAM_BUILD_TESTS=OFF -DPARKSLAM_BUILD_BENCHMARKS=OFF "${CACHE_ARGS[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_all

all=(fuzz_sensor_csv fuzz_observations_jsonl fuzz_dataset_yaml fuzz_groundtruth fuzz_map_json
     fuzz_scenario_yaml fuzz_rig_yaml fuzz_tum fuzz_g2o fuzz_ps2_labels fuzz_numeric_csv fuzz_image_index
     fuzz_image_header fuzz_homography_rig)
[ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")
for t in "${targets[@]}"; do
  [ -x "build-fuzz/bin/$t" ] || { echo "fuzz.sh: no target '$t' (${all[*]})" >&2; exit 2; }
done

# The parser's own sources of each target, for the coverage column.
sources_of() {
  case "$1" in
    fuzz_sensor_csv|fuzz_observations_jsonl) echo "io/dataset.cc io/json_util.cc io/text_util.cc" ;;
    fuzz_dataset_yaml) echo "io/dataset.cc io/scenario_yaml.cc io/yaml_util.cc" ;;
    fuzz_groundtruth) echo "io/dataset.cc io/tum.cc io/map_json.cc io/json_util.cc" ;;
    fuzz_map_json) echo "io/map_json.cc io/json_util.cc" ;;
    fuzz_scenario_yaml) echo "io/scenario_yaml.cc io/yaml_util.cc" ;;
    fuzz_rig_yaml) echo "io/rig_yaml.cc io/yaml_util.cc" ;;
    fuzz_tum) echo "io/tum.cc io/text_util.cc" ;;
    fuzz_g2o) echo "io/g2o.cc io/text_util.cc" ;;
    fuzz_ps2_labels) echo "io/ps2_labels.cc io/json_util.cc" ;;
    fuzz_numeric_csv) echo "io/numeric_csv.cc io/text_util.cc" ;;
    fuzz_image_index) echo "io/image_folder.cc io/text_util.cc" ;;
    fuzz_image_header) echo "io/image_header.cc" ;;
    fuzz_homography_rig) echo "io/homography_rig.cc" ;;
  esac
}

out=build-fuzz/runs
mkdir -p "$out" build-fuzz/findings
rm -rf build-fuzz/seeds
build-fuzz/bin/fuzz_seeds build-fuzz/seeds
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t"
  cp -n build-fuzz/seeds/"$t"/* "build-fuzz/corpus/$t/" 2>/dev/null || true
done
for f in config/worlds/*.yaml; do cp -n "$f" build-fuzz/corpus/fuzz_scenario_yaml/ 2>/dev/null || true; done

run_one() {
  local t=$1
  "build-fuzz/bin/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=16384 -print_final_stats=1 -artifact_prefix="build-fuzz/findings/$t-" \
    "build-fuzz/corpus/$t" >"$out/$t.log" 2>&1
  echo "$t exit $?" >>"$out/$t.log"
}
export -f run_one
export seconds out
echo "fuzz.sh: ${#targets[@]} targets, ${seconds} s each, ${parallel} at a time"
printf '%s\n' "${targets[@]}" | xargs -P "$parallel" -I{} bash -c 'run_one {}; echo "  done {}"'

# The table.
status=0
printf '%-24s %12s %9s %8s %8s  %s\n' target executions "exec/s" edges corpus result
for t in "${targets[@]}"; do
  log="$out/$t.log"
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | awk '{print $2}')
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | awk '{print $2}')
  edges=$(grep -E '^#[0-9]+' "$log" | tail -1 | grep -o 'cov: [0-9]*' | awk '{print $2}')
  result=ok
  if ! grep -q "^$t exit 0$" "$log"; then result="FINDING (see $log)"; status=1; fi
  corpus=$(find "build-fuzz/corpus/$t" -type f | wc -l)
  printf '%-24s %12s %9s %8s %8s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "${edges:-?}" \
    "$corpus" "$result"
done

if [ "$coverage" = 1 ]; then
  echo "fuzz.sh: coverage of the parsers' source files by the corpora (llvm-cov; the files"
  echo "also hold writers, which no parser calls)"
  flags="-fprofile-instr-generate -fcoverage-mapping"
  CXX=clang++ cmake -S . -B build-fuzz-cov -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPARKSLAM_FUZZ=ON \
    -DPARKSLAM_BUILD_TESTS=OFF -DPARKSLAM_BUILD_BENCHMARKS=OFF \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fprofile-instr-generate" >/dev/null
  cmake --build build-fuzz-cov -j"$(nproc)" --target fuzz_all >/dev/null
  rm -rf build-fuzz-cov/profiles
  mkdir -p build-fuzz-cov/profiles
  for t in "${targets[@]}"; do
    LLVM_PROFILE_FILE="build-fuzz-cov/profiles/$t.profraw" \
      "build-fuzz-cov/bin/$t" -runs=0 "build-fuzz/corpus/$t" >/dev/null 2>&1 || true
    llvm-profdata merge -sparse "build-fuzz-cov/profiles/$t.profraw" \
      -o "build-fuzz-cov/profiles/$t.profdata"
    files=()
    for s in $(sources_of "$t"); do files+=("src/parkslam/$s"); done
    # TOTAL regions missed cover functions missed executed lines missed cover branches missed cover
    llvm-cov report "build-fuzz-cov/bin/$t" -instr-profile="build-fuzz-cov/profiles/$t.profdata" \
      "${files[@]}" 2>/dev/null |
      awk -v t="$t" -v s="$(sources_of "$t")" '/^TOTAL/ {
        printf "%-24s lines %s (%d of %d), branches %s, functions %s  [%s]\n", t, $10, $8 - $9, $8, $13, $7, s }'
  done
fi
exit $status
