# FindBullet: Bullet Physics as Debian packages it (libbullet-dev). It takes the place of
# CMake's own FindBullet, which sets variables only and ignores the version asked for.
# Defines Bullet_FOUND, Bullet_VERSION (from BT_BULLET_VERSION in LinearMath/btScalar.h,
# 324 -> 3.24) and the imported target Bullet::Bullet (BulletDynamics, BulletCollision,
# LinearMath: the parts dawnforge::sim uses). Installed with the package, so that
# find_package(dawnforge) makes the same target.
find_path(Bullet_INCLUDE_DIR btBulletDynamicsCommon.h PATH_SUFFIXES bullet)
set(_bullet_libraries)
foreach(_bullet_part BulletDynamics BulletCollision LinearMath)
  find_library(Bullet_${_bullet_part}_LIBRARY ${_bullet_part})
  mark_as_advanced(Bullet_${_bullet_part}_LIBRARY)
  list(APPEND _bullet_libraries Bullet_${_bullet_part}_LIBRARY)
endforeach()
if(Bullet_INCLUDE_DIR AND EXISTS ${Bullet_INCLUDE_DIR}/LinearMath/btScalar.h)
  file(STRINGS ${Bullet_INCLUDE_DIR}/LinearMath/btScalar.h _bullet_version REGEX "^#define BT_BULLET_VERSION [0-9]+")
  string(REGEX MATCH "[0-9]+$" _bullet_version "${_bullet_version}")
  if(_bullet_version)
    math(EXPR _bullet_major "${_bullet_version} / 100")
    math(EXPR _bullet_minor "${_bullet_version} % 100")
    set(Bullet_VERSION ${_bullet_major}.${_bullet_minor})
  endif()
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Bullet REQUIRED_VARS Bullet_INCLUDE_DIR ${_bullet_libraries} VERSION_VAR Bullet_VERSION)
if(Bullet_FOUND AND NOT TARGET Bullet::Bullet)
  add_library(Bullet::Bullet INTERFACE IMPORTED)
  set_target_properties(Bullet::Bullet PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES ${Bullet_INCLUDE_DIR}
    INTERFACE_LINK_LIBRARIES "${Bullet_BulletDynamics_LIBRARY};${Bullet_BulletCollision_LIBRARY};${Bullet_LinearMath_LIBRARY}")
endif()
mark_as_advanced(Bullet_INCLUDE_DIR)
unset(_bullet_libraries)
unset(_bullet_version)
