# The installed CMake package: CTSplinesConfig.cmake and its version file beside the exported
# targets that vtk_module_build writes (CTSplines-targets.cmake, module properties).
include(CMakePackageConfigHelpers)
set(CTSPLINES_CMAKE_DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/CTSplines")
# Only what the module's public interface needs; its private dependencies are linked into
# libCTSplinesFilters already.
set(CTSPLINES_PACKAGE_VTK_COMPONENTS "CommonCore CommonDataModel CommonExecutionModel")
# CTSplines::IOCAD, when built, is in the same export; the toolkits it links are OpenCASCADE's
# targets, so the package finds OpenCASCADE as the build did (in the same folder).
if(TARGET CTSplines::IOCAD)
  set(CTSPLINES_PACKAGE_HAS_IOCAD ON)
else()
  set(CTSPLINES_PACKAGE_HAS_IOCAD OFF)
endif()
configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/CTSplinesConfig.cmake.in"
  "${CMAKE_BINARY_DIR}/${CTSPLINES_CMAKE_DESTINATION}/CTSplinesConfig.cmake"
  INSTALL_DESTINATION "${CTSPLINES_CMAKE_DESTINATION}")
write_basic_package_version_file(
  "${CMAKE_BINARY_DIR}/${CTSPLINES_CMAKE_DESTINATION}/CTSplinesConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${CMAKE_BINARY_DIR}/${CTSPLINES_CMAKE_DESTINATION}/CTSplinesConfig.cmake"
  "${CMAKE_BINARY_DIR}/${CTSPLINES_CMAKE_DESTINATION}/CTSplinesConfigVersion.cmake"
  DESTINATION "${CTSPLINES_CMAKE_DESTINATION}")
