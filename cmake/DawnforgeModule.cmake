# dawnforge_add_module(NAME [SOURCES ...]): the library of one top-level folder, as
# target dawnforge_<NAME> with alias and export name dawnforge::<NAME>. Public headers
# live in <folder>/include/dawnforge/<folder>/; a folder without sources yet is an
# INTERFACE library so that nothing pretends to be built.
function(dawnforge_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  set(target dawnforge_${name})
  if(ARG_SOURCES)
    add_library(${target} STATIC ${ARG_SOURCES})
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>
      PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
  endif()
  add_library(dawnforge::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS ${target} EXPORT dawnforgeTargets ARCHIVE DESTINATION lib)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION include)
  endif()
endfunction()
