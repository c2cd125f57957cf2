# Helpers shared by every stage: warnings, sanitizers, module targets.

# Warnings are errors in our own code; third-party headers come in as SYSTEM includes. The
# release build enforces them; the sanitizer build (compiled at -O1, where GCC's flow-sensitive
# warnings differ and the instrumentation adds false positives) prints them without failing.
function(taskmap_set_warnings target)
  set(_werror -Werror)
  if(TASKMAP_SANITIZE)
    set(_werror "")
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow=local -Wnon-virtual-dtor ${_werror}>)
endfunction()

if(TASKMAP_SANITIZE)
  string(REPLACE "," ";" _taskmap_san_list "${TASKMAP_SANITIZE}")
  string(REPLACE ";" "," _taskmap_san_flags "${_taskmap_san_list}")
  # -O1 with line tables only (-g1; after the build type's flags, so they win): what
  # AddressSanitizer's documentation recommends, stack traces keep file and line, and the
  # compile takes less than half the time of -O2 -g (measured on meshes/src/convex_decomposition.cpp,
  # the CGAL translation units dominate the sanitizer build: 737 s against 1688 s, same machine).
  add_compile_options(-O1 -g1 -fsanitize=${_taskmap_san_flags} -fno-omit-frame-pointer
    -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${_taskmap_san_flags})
endif()

# taskmap_add_module(<stage> [SOURCES ...] [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# SOURCES default to every src/*.cpp of the stage.
# Creates library taskmap_<stage>, alias taskmap::<stage>, public headers in
# <stage>/include, installed and exported.
function(taskmap_add_module stage)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT ARG_SOURCES)
    file(GLOB_RECURSE ARG_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  endif()
  set(target taskmap_${stage})
  if(NOT ARG_SOURCES)
    # A stage whose sources are not written yet: headers only.
    add_library(${target} INTERFACE)
    add_library(taskmap::${stage} ALIAS ${target})
    target_include_directories(${target} INTERFACE
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${stage})
    install(TARGETS ${target} EXPORT TaskMapTargets)
    return()
  endif()
  add_library(${target} ${ARG_SOURCES})
  add_library(taskmap::${stage} ALIAS ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES
    EXPORT_NAME ${stage}
    OUTPUT_NAME taskmap_${stage}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_compile_definitions(${target} PRIVATE TASKMAP_VERSION="${PROJECT_VERSION}")
  taskmap_set_warnings(${target})
  install(TARGETS ${target} EXPORT TaskMapTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
