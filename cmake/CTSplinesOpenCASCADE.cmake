# OpenCASCADE for CTSplines::IOCAD. Debian's -dev packages ship a CMake config whose DataExchange
# component references toolkits that are not installed with them (TKXCAF needs TKCAF, TKV3d, ...),
# so only the geometry/topology components are taken from the config and the STEP/IGES toolkits
# are imported here by hand. Sets OpenCASCADE_FOUND and CTSPLINES_OCCT_TOOLKITS.
find_package(OpenCASCADE CONFIG QUIET
  COMPONENTS FoundationClasses ModelingData ModelingAlgorithms)
set(CTSPLINES_OCCT_TOOLKITS TKernel TKMath TKG2d TKG3d TKGeomBase TKBRep TKGeomAlgo TKTopAlgo
  TKPrim TKBO TKShHealing TKXSBase TKSTEPBase TKSTEPAttr TKSTEP209 TKSTEP TKIGES)
if(OpenCASCADE_FOUND)
  foreach(_tk TKXSBase TKSTEPBase TKSTEPAttr TKSTEP209 TKSTEP TKIGES)
    if(NOT TARGET ${_tk})
      find_library(CTSPLINES_${_tk}_LIBRARY ${_tk} HINTS "${OpenCASCADE_LIBRARY_DIR}")
      if(NOT CTSPLINES_${_tk}_LIBRARY)
        message(STATUS "CTSplines: OpenCASCADE toolkit ${_tk} not found, CTSplines::IOCAD disabled")
        set(OpenCASCADE_FOUND FALSE)
        break()
      endif()
      add_library(${_tk} SHARED IMPORTED)
      set_target_properties(${_tk} PROPERTIES IMPORTED_LOCATION "${CTSPLINES_${_tk}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCASCADE_INCLUDE_DIR}")
    endif()
  endforeach()
endif()
