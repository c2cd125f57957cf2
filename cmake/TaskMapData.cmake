# Bundled data, found by the tool, the library and the Python package relative to themselves
# (core/include/taskmap/core/data_dir.hpp): <prefix>/share/taskmap with hands/, objects/, maps/,
# robots/ and regression/ (cases.json, golden/). Staged and installed whatever is built (tool or
# not), so `pip install .` carries it in the wheel (python/build_backend.py) and a Python user
# finds it beside libtaskmap_core. The build tree stages the same layout in <build>/share/taskmap
# with links into the source tree (so `regress --update` writes the source tree's goldens); the
# install tree gets copies and works without the source tree.
set(_data ${PROJECT_BINARY_DIR}/share/taskmap)
file(MAKE_DIRECTORY ${_data}/regression)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/meshes/hands ${_data}/hands SYMBOLIC)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/meshes/objects ${_data}/objects SYMBOLIC)
# maps/ (checked-in reference task maps, `taskmap reach --map basket_humanoid`).
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/meshes/maps ${_data}/maps SYMBOLIC)
# robots/ (the Panda arm of reaching/, installed by reaching/CMakeLists.txt).
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/reaching/robots ${_data}/robots SYMBOLIC)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/tests/regression/golden ${_data}/regression/golden SYMBOLIC)
# The suite's paths are relative to its file: ../../meshes/<x> in the source tree, ../<x> here.
set(_cases_src ${PROJECT_SOURCE_DIR}/tests/regression/cases.json)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_cases_src})
file(READ ${_cases_src} _cases)
string(REPLACE "../../meshes/" "../" _cases "${_cases}")
file(CONFIGURE OUTPUT ${_data}/regression/cases.json CONTENT "${_cases}" @ONLY)
set(_share ${CMAKE_INSTALL_DATADIR}/taskmap)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/meshes/hands/ DESTINATION ${_share}/hands)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/meshes/objects/ DESTINATION ${_share}/objects
  FILES_MATCHING PATTERN "*.obj" PATTERN "*.md")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/meshes/maps/ DESTINATION ${_share}/maps
  FILES_MATCHING PATTERN "*.h5" PATTERN "*.md")
install(FILES ${_data}/regression/cases.json DESTINATION ${_share}/regression)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tests/regression/golden/ DESTINATION ${_share}/regression/golden)
