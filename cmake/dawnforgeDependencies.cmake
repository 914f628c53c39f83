# The third-party packages that dawnforge's libraries link, each with its minimum version.
# The libraries are static, so whatever links them links these too: this one list serves
# the build (cmake/Dependencies.cmake includes it) and the installed package
# (dawnforgeConfig.cmake includes it, so find_package(dawnforge) finds them). A package
# added to a module's target_link_libraries belongs here; the install test
# (tests/install) fails when the package misses one.
#
# In the build a missing package stops the configure. In the installed package, the config
# sets DAWNFORGE_FINDING_PACKAGE first: a missing package makes find_package(dawnforge)
# fail with a message naming it (find_dependency), and this file returns early.
include(CMakeFindDependencyMacro)
find_package(PkgConfig QUIET)

macro(dawnforge_find_dependency)
  if(DAWNFORGE_FINDING_PACKAGE)
    find_dependency(${ARGV})
  else()
    find_package(${ARGV} REQUIRED)
  endif()
endmacro()

# pkg-config modules become the imported target PkgConfig::<prefix>.
macro(dawnforge_find_pkg_config prefix module)
  if(DAWNFORGE_FINDING_PACKAGE)
    if(PKG_CONFIG_FOUND)
      pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
    endif()
    if(NOT ${prefix}_FOUND)
      set(dawnforge_NOT_FOUND_MESSAGE "dawnforge needs ${module} (found through pkg-config), which was not found")
      set(dawnforge_FOUND FALSE)
      return()
    endif()
  else()
    pkg_check_modules(${prefix} REQUIRED IMPORTED_TARGET ${module})
  endif()
endmacro()

# FindBullet.cmake sits next to this file, in the source tree as in the installed package.
list(PREPEND CMAKE_MODULE_PATH ${CMAKE_CURRENT_LIST_DIR})

dawnforge_find_dependency(Threads)                  # through TBB and OpenVDB
dawnforge_find_dependency(glm 0.9.9)                # core (public: its maths type)
dawnforge_find_dependency(nlohmann_json 3.11)       # every file format
dawnforge_find_dependency(tinyobjloader)            # core: OBJ import
dawnforge_find_dependency(TinyGLTF 2.7)             # core, exporters: glTF
dawnforge_find_dependency(assimp 5.2)               # core: FBX, Collada, STL, PLY, OFF import (below)
dawnforge_find_dependency(TBB 2021)                 # procgen, sim, runtime: parallel loops
dawnforge_find_dependency(CGAL 5.5)                 # core, procgen, sim (with GMP and MPFR)
dawnforge_find_dependency(Bullet 3.24)              # sim: rigid bodies (FindBullet.cmake)
dawnforge_find_dependency(Eigen3 3.3 NO_MODULE)     # sim: the bond graph's sparse solve
dawnforge_find_dependency(OpenEXR 3.1)              # exporters: VAT textures; bake: overlook.exr
dawnforge_find_dependency(embree 3.13)              # bake: ray queries (Embree 3)
dawnforge_find_dependency(meshoptimizer 0.18)       # world: HLOD simplification
dawnforge_find_dependency(glfw3 3.3)                # runtime: the window
dawnforge_find_dependency(OpenGL COMPONENTS EGL)    # runtime: the headless context
dawnforge_find_pkg_config(epoxy epoxy>=1.5)         # runtime: GL function loading
dawnforge_find_pkg_config(stb stb)                  # exporters: PNG

# Assimp's package puts libdraco.so.7 on its users' link lines, and Debian's draco exports a
# tinygltf of its own under tinygltf's names: linked directly, it is searched before
# libtinygltf.so and takes our tinygltf calls (a crash). Link libassimp.so alone; it loads
# draco itself, after every library linked directly.
if(NOT TARGET assimp::libassimp)
  add_library(assimp::libassimp SHARED IMPORTED)
  get_target_property(_assimp_location assimp::assimp LOCATION)
  get_target_property(_assimp_includes assimp::assimp INTERFACE_INCLUDE_DIRECTORIES)
  set_target_properties(assimp::libassimp PROPERTIES
    IMPORTED_LOCATION ${_assimp_location} INTERFACE_INCLUDE_DIRECTORIES "${_assimp_includes}")
endif()

# sim: rough cut surfaces. OpenVDB ships its find module in its own folder
# (<prefix>/lib/<arch>/cmake/OpenVDB on Debian). That folder also holds a FindTBB and a
# FindOpenEXR, so it goes last, after TBB and OpenEXR were found through their own configs.
set(_dawnforge_openvdb_dirs)
foreach(_dawnforge_prefix IN LISTS CMAKE_PREFIX_PATH CMAKE_SYSTEM_PREFIX_PATH)
  foreach(_dawnforge_lib IN ITEMS lib/${CMAKE_LIBRARY_ARCHITECTURE} lib64 lib)
    list(APPEND _dawnforge_openvdb_dirs ${_dawnforge_prefix}/${_dawnforge_lib}/cmake/OpenVDB)
  endforeach()
endforeach()
find_path(OpenVDB_MODULE_DIR FindOpenVDB.cmake PATHS ${_dawnforge_openvdb_dirs} NO_DEFAULT_PATH
  DOC "The folder of OpenVDB's FindOpenVDB.cmake")
unset(_dawnforge_openvdb_dirs)
if(OpenVDB_MODULE_DIR)
  list(APPEND CMAKE_MODULE_PATH ${OpenVDB_MODULE_DIR})
endif()
dawnforge_find_dependency(OpenVDB 10)
