# Every third-party package dawnforge uses, found once with its minimum version.
# All come from Debian's packages (the ./run script installs them); nothing is downloaded.
# Each module links what it needs PRIVATE (ARCHITECTURE.md: no third-party type in a
# public header of another module), except GLM, which is core's public maths type.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)

find_package(glm 0.9.9 REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(TinyGLTF 2.7 REQUIRED)
find_package(assimp 5.2 REQUIRED)
find_package(TBB 2021 REQUIRED)
find_package(CGAL 5.5 REQUIRED)
find_package(Bullet 3.24 REQUIRED)
find_package(embree 3.13 REQUIRED)
find_package(OpenEXR 3.1 REQUIRED)
find_package(glfw3 3.3 REQUIRED)
find_package(OpenGL REQUIRED COMPONENTS EGL OpenGL)
pkg_check_modules(epoxy REQUIRED IMPORTED_TARGET epoxy>=1.5)
pkg_check_modules(stb REQUIRED IMPORTED_TARGET stb)
# OpenVDB ships its find module in its own folder on Debian.
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB /usr/lib/cmake/OpenVDB)
find_package(OpenVDB 10 REQUIRED)

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

# Bullet's package file sets variables only; give it a target like the others.
if(NOT TARGET Bullet::Bullet)
  add_library(Bullet::Bullet INTERFACE IMPORTED)
  set(_bullet_libs)
  foreach(lib BulletDynamics BulletCollision LinearMath)
    find_library(_bullet_${lib} ${lib} HINTS ${BULLET_ROOT_DIR}/${BULLET_LIBRARY_DIRS} REQUIRED)
    list(APPEND _bullet_libs ${_bullet_${lib}})
  endforeach()
  set_target_properties(Bullet::Bullet PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES ${BULLET_ROOT_DIR}/${BULLET_INCLUDE_DIR}
    INTERFACE_LINK_LIBRARIES "${_bullet_libs}")
endif()

if(DAWNFORGE_BUILD_TESTS)
  find_package(GTest 1.12 REQUIRED)
endif()
if(DAWNFORGE_BUILD_BENCH)
  find_package(benchmark 1.7 REQUIRED)
endif()
