# The core runs on a car: it must not link the simulator side (issue 14's
# layering). parkslam_check_layering(CORE a b ... FORBIDDEN x y ...) walks
# each core target's link libraries, transitively through project targets,
# and stops the configuration if it reaches a forbidden one, naming the path.

function(_parkslam_collect_links target path forbidden out_violation)
  get_target_property(links ${target} LINK_LIBRARIES)
  if(NOT links)
    set(${out_violation} "" PARENT_SCOPE)
    return()
  endif()
  foreach(link IN LISTS links)
    if(NOT TARGET ${link})
      continue()
    endif()
    if(link IN_LIST forbidden)
      set(${out_violation} "${path} -> ${link}" PARENT_SCOPE)
      return()
    endif()
    get_target_property(type ${link} TYPE)
    get_target_property(imported ${link} IMPORTED)
    if(imported OR type STREQUAL "INTERFACE_LIBRARY")
      continue()
    endif()
    _parkslam_collect_links(${link} "${path} -> ${link}" "${forbidden}" violation)
    if(violation)
      set(${out_violation} "${violation}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out_violation} "" PARENT_SCOPE)
endfunction()

function(parkslam_check_layering)
  cmake_parse_arguments(ARG "" "" "CORE;FORBIDDEN" ${ARGN})
  foreach(core IN LISTS ARG_CORE)
    if(NOT TARGET ${core})
      message(FATAL_ERROR "parkslam_check_layering: no target ${core}")
    endif()
    _parkslam_collect_links(${core} "${core}" "${ARG_FORBIDDEN}" violation)
    if(violation)
      message(FATAL_ERROR
        "Layering: core target ${core} links a simulator-side target: ${violation}. "
        "The core (docs/architecture.md) must build without the simulator, renderer, "
        "evaluation, file formats or the experiment harness.")
    endif()
  endforeach()
endfunction()
