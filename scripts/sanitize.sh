#!/usr/bin/env bash
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in
# build-asan/ (-O1 -g1: half the compile time of -O2 -g, with line numbers
# in reports; no benchmarks) and runs the tests there. CI runs it after
# scripts/test.sh. Extra arguments go to ctest (e.g. -R io_test).
#
# The slowest tests run once, in scripts/test.sh's Release suite, and not
# here: the ones that took over 12 s each under the sanitizers (long drives,
# rendered frames, the CLI script, the format check), 34 of 743 tests but
# 80 % of a sanitized run's 19 minutes when measured; four that paint a
# realistic lot's floor (3 to 40 s each in Release) joined them without a
# sanitized measurement. Every other test runs here too.
# SANITIZE_ALL=1 runs them all. One name a line, without groups of their
# own: CMake's regular expressions take at most 10 groups, and past that
# ctest says "Too many parentheses" and excludes nothing.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/compiler_cache.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DPARKSLAM_SANITIZE=ON \
  -DPARKSLAM_BUILD_BENCHMARKS=OFF "${CACHE_ARGS[@]}" >/dev/null
cmake --build build-asan -j"$(nproc)"
# Leaks of libraries' own one-time allocations (fontconfig, OpenCV's
# thread pools) are not ours: leak checking is off, the rest is on.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
slow=(cli_test format_check install_test
  'DeadReckoningTest\.GyroOnlyAndDisturbedCompassDriftLessThanOnePercent'
  'FaultToleranceTest\.'
  'SoakTest\.'
  'KidnapTest\.RelocalizesInAlmostAllTrials'
  'OdometryConsistencyTest\.NeesInsideChiSquareBandOnDefaultDrive'
  'OnlineMappingTest\.BackgroundSolveKeepsTheMapAtBatchAccuracyAlongTheDrive'
  'LiveSystemTest\.OnCameraFramesWaitingForPerceptionThePosesAreLocalizesOwn'
  'LiveSystemTest\.FramesFasterThanPerceptionAreDroppedAndTheCarIsStillTracked'
  'PerceptionSourceTest\.ReplacesObservationsByWhatTheCamerasSee'
  'ReportTest\.EveryFigureAgreesWithMetricsJson'
  'ReportTest\.OpensInHeadlessChromiumAndLinksPlotsAndMap'
  'ReportTest\.TheCommandWritesTheSamePageAndRefusesAnEmptyFolder'
  'SceneRendererTest\.ChromaNoiseColoursTheFineScale'
  'SceneRendererTest\.LabelledMarkingPointsLieOnTheirRenderedJunctions'
  'SceneRendererTest\.RendersColourFisheyesAndATopViewOfTheRigsSizes'
  'SceneRendererTest\.SameSceneSameBytes'
  'SceneRendererTest\.RoundedCornersShowTheFloorTheBoxsCornerHid'
  'SceneRendererTest\.SharperUnitsKeepTheirLabels'
  'SceneRendererTest\.SolidsHideTheFloorAndItsLabels'
  'SceneRendererTest\.StraightSeamsKeepTheirLabels'
  'SceneRendererTest\.TheBumpersLipHidesADomeAheadOfTheCar'
  'SensorStreamTest\.LiveRenderingReplacesTheObservationsWithWhatTheCamerasSee'
  'SensorStreamTest\.OnPixelsTheLocalizerUsesSlotsAndTags'
  'SensorStreamTest\.InARealisticLookTheLocalizerStillUsesSlotsAndTags'
  'LotRendererTest\.TheFloorStaysInPlaceAsTheCarMoves'
  'LotRendererTest\.SlotLinesShowBrighterThanTheFloor'
  'LotRendererTest\.TheFrontCameraSeesTheTagLibapriltagDecodes'
  'SlotIdReaderTest\.ReadsTheDefaultLotInRenderedTopViews'
  'StandardGraphsTest\.M3500sRandomOutliersAreAllRejectedAndTheCleanOptimumReached'
  'TraceFollowingTest\.DeadReckoningAloneDriftsAway'
  'TraceFollowingTest\.FollowsTheTraceOnPixels'
  'TraceFollowingTest\.RealisticVehicleRepeatsTheTraceAt4And10Kmh'
  'TraceFollowingTest\.SafetyStopsInRandomKidnapsAndBlackouts')
exclude=()
if [ "${SANITIZE_ALL:-0}" != 1 ]; then
  exclude=(-E "^($(IFS='|'; echo "${slow[*]}"))")
fi
cd build-asan
ctest --output-on-failure -j"$(nproc)" "${exclude[@]}" "$@"
