# parkslam_install_core(TARGETS t ... MODULES m ...): installs the core's
# libraries (exported as parkslam::<name without the parkslam_ prefix>, so
# parkslam_localization is parkslam::localization), the headers of its
# modules (src/parkslam/<m>/, test helpers left out), the trained networks
# (share/parkslam/models) and a CMake package in lib/cmake/parkslam.
include(CMakePackageConfigHelpers)

function(parkslam_install_core)
  cmake_parse_arguments(ARG "" "" "TARGETS;MODULES" ${ARGN})
  foreach(target IN LISTS ARG_TARGETS)
    string(REGEX REPLACE "^parkslam_" "" short "${target}")
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${short})
  endforeach()
  install(TARGETS ${ARG_TARGETS} EXPORT parkslamTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  foreach(module IN LISTS ARG_MODULES)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/parkslam/${module}/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/parkslam/${module}
            FILES_MATCHING PATTERN "*.h"
            PATTERN "*test_util.h" EXCLUDE
            PATTERN "testdata" EXCLUDE)
  endforeach()
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/models/
          DESTINATION ${CMAKE_INSTALL_DATADIR}/parkslam/models
          FILES_MATCHING PATTERN "*.onnx" PATTERN "*.json")
  set(package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/parkslam)
  install(EXPORT parkslamTargets NAMESPACE parkslam:: DESTINATION ${package_dir})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/parkslamConfig.cmake.in
                                ${PROJECT_BINARY_DIR}/parkslamConfig.cmake
                                INSTALL_DESTINATION ${package_dir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/parkslamConfigVersion.cmake
                                   VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/parkslamConfig.cmake
                ${PROJECT_BINARY_DIR}/parkslamConfigVersion.cmake
          DESTINATION ${package_dir})
endfunction()
