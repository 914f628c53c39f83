# FindTetGen: TetGen 1.5 as Debian packages it (libtet1.5-dev: tetgen.h and libtet).
# Defines TetGen_FOUND and the imported target TetGen::TetGen (with TETLIBRARY set,
# which the header needs when TetGen is used as a library).
find_path(TetGen_INCLUDE_DIR tetgen.h)
find_library(TetGen_LIBRARY NAMES tet tetgen)
if(TetGen_INCLUDE_DIR AND EXISTS ${TetGen_INCLUDE_DIR}/tetgen.h)
  file(STRINGS ${TetGen_INCLUDE_DIR}/tetgen.h _tetgen_version REGEX "^// Version [0-9.]+")
  string(REGEX MATCH "[0-9]+\\.[0-9]+(\\.[0-9]+)?" TetGen_VERSION "${_tetgen_version}")
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(TetGen REQUIRED_VARS TetGen_LIBRARY TetGen_INCLUDE_DIR VERSION_VAR TetGen_VERSION)
if(TetGen_FOUND AND NOT TARGET TetGen::TetGen)
  add_library(TetGen::TetGen UNKNOWN IMPORTED)
  set_target_properties(TetGen::TetGen PROPERTIES
    IMPORTED_LOCATION ${TetGen_LIBRARY}
    INTERFACE_INCLUDE_DIRECTORIES ${TetGen_INCLUDE_DIR}
    INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)
endif()
mark_as_advanced(TetGen_INCLUDE_DIR TetGen_LIBRARY)
