# SPDX-License-Identifier: MIT
# Libraries whose folders are layers (core/, ui/): their sources globbed folder by folder, and an
# include root that shows their clients the library's own tree and nothing else of the project.

# pb_layer_sources(<out-var> <folder>...): every .cpp and .hpp of each folder of the calling
# directory (one concept per header: a file in a layer's folder belongs to the library).
function(pb_layer_sources out)
  set(sources)
  foreach(folder IN LISTS ARGN)
    file(GLOB found CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.cpp
                                      ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.hpp)
    list(APPEND sources ${found})
  endforeach()
  set(${out} ${sources} PARENT_SCOPE)
endfunction()

# pb_expose_only(<target> <name>): the target's clients include "<name>/..." (a build folder
# holding a link to the calling directory) and nothing else of the tree, so an include of another
# library's or a tool's header fails to compile instead of working by accident.
function(pb_expose_only target name)
  set(root ${CMAKE_BINARY_DIR}/include/${name}-only)
  file(MAKE_DIRECTORY ${root})
  file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR} ${root}/${name} SYMBOLIC)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${root}>)
endfunction()
