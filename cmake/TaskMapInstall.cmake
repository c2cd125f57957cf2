# Exported, versioned CMake package: find_package(TaskMap) then link taskmap::taskmap.
include(CMakePackageConfigHelpers)
set(TASKMAP_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/TaskMap)
install(EXPORT TaskMapTargets NAMESPACE taskmap:: DESTINATION ${TASKMAP_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/TaskMapConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/TaskMapConfig.cmake INSTALL_DESTINATION ${TASKMAP_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/TaskMapConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/TaskMapConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/TaskMapConfigVersion.cmake DESTINATION ${TASKMAP_CMAKE_DIR})
