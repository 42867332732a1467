# Bullet from Debian's package: its BulletConfig.cmake sets only variables (include directories
# relative to BULLET_ROOT_DIR, bare library names). Wrap them once in an imported INTERFACE
# target so that our targets, and users' projects through hydrotexConfig.cmake, link one name.
# Installed beside hydrotexConfig.cmake so that find_package(hydrotex) can include it.
if(NOT TARGET hydrotex::BulletDependency)
  find_package(Bullet CONFIG REQUIRED)
  set(_hydrotex_bullet_include "${BULLET_INCLUDE_DIRS}")
  if(NOT IS_ABSOLUTE "${_hydrotex_bullet_include}")
    set(_hydrotex_bullet_include "${BULLET_ROOT_DIR}/${_hydrotex_bullet_include}")
  endif()
  set(_hydrotex_bullet_libdir "${BULLET_LIBRARY_DIRS}")
  if(NOT IS_ABSOLUTE "${_hydrotex_bullet_libdir}")
    set(_hydrotex_bullet_libdir "${BULLET_ROOT_DIR}/${_hydrotex_bullet_libdir}")
  endif()
  # The three libraries a rigid-body world needs, and BulletSoftBody for soft bodies
  # (SoftBodyBuoyancy; btSoftRigidDynamicsWorld), in link order (dependents first).
  set(_hydrotex_bullet_libraries "")
  foreach(_component BulletSoftBody BulletDynamics BulletCollision LinearMath)
    find_library(HYDROTEX_BULLET_${_component}_LIBRARY NAMES ${_component}
                 HINTS "${_hydrotex_bullet_libdir}" REQUIRED)
    list(APPEND _hydrotex_bullet_libraries "${HYDROTEX_BULLET_${_component}_LIBRARY}")
  endforeach()
  add_library(hydrotex::BulletDependency INTERFACE IMPORTED)
  set_target_properties(hydrotex::BulletDependency PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_hydrotex_bullet_include}"
    INTERFACE_LINK_LIBRARIES "${_hydrotex_bullet_libraries}")
  if(BULLET_DEFINITIONS)
    set_property(TARGET hydrotex::BulletDependency PROPERTY INTERFACE_COMPILE_DEFINITIONS ${BULLET_DEFINITIONS})
  endif()
endif()
