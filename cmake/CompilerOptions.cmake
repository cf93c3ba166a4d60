# One warnings policy for every target of the project (STYLE.md, practice 1).
option(PARKSLAM_WERROR "Treat compiler warnings as errors (on in CI)" OFF)

function(parkslam_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor -Wold-style-cast)
  if(PARKSLAM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# A library of the core: sources listed explicitly, public include root at src/.
function(parkslam_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} ${ARG_SOURCES})
  add_library(parkslam::${name} ALIAS ${name})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_compile_features(${name} PUBLIC cxx_std_20)
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  parkslam_set_warnings(${name})
endfunction()

# A definition that names a folder of the checkout (PARKSLAM_CONFIG_DIR
# "/path/to/clone/config") changes the compiler command of every source it
# reaches, so each of them misses the compiler cache in a clone elsewhere
# (CI's fresh clone). Such definitions go to the few sources that read them,
# compiled outside the unity files, so that the rest of the target still hits.
function(parkslam_source_definitions)
  cmake_parse_arguments(ARG "" "" "FILES;DEFINITIONS" ${ARGN})
  set_source_files_properties(${ARG_FILES} PROPERTIES COMPILE_DEFINITIONS "${ARG_DEFINITIONS}"
                                                      SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()

# A GoogleTest executable registered with CTest.
function(parkslam_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest_main GTest::gmock)
  parkslam_set_warnings(${name})
  # Eight test files to a unity file: GoogleTest's and gmock's inline code
  # is compiled once for them, not once each (CI builds everything twice).
  # So helpers in a test file's anonymous namespace need names of their
  # own within the test target.
  set_target_properties(${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES ENVIRONMENT "PARKSLAM_SHARED_DATA=${PARKSLAM_SHARED_DATA}")
endfunction()
