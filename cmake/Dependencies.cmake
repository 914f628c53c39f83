# Every third-party package dawnforge uses, found once with its minimum version.
# All come from Debian's packages (the ./run script installs them); nothing is downloaded.
# Each module links what it needs PRIVATE (ARCHITECTURE.md: no third-party type in a
# public header of another module), except GLM, which is core's public maths type.

# What the libraries link: one list, shared with the installed package.
include(${CMAKE_CURRENT_LIST_DIR}/dawnforgeDependencies.cmake)

# What only the build uses: the command line, the tests, the benchmarks.
find_package(CLI11 2.1 REQUIRED)
find_package(embree 3.13 REQUIRED)  # for bake/, an INTERFACE library until its issue lands
if(DAWNFORGE_BUILD_TESTS)
  find_package(GTest 1.12 REQUIRED)
endif()
if(DAWNFORGE_BUILD_BENCH)
  find_package(benchmark 1.7 REQUIRED)
endif()
