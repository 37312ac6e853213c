# Script of the Install.CxxExample test (see CMakeLists.txt). Variables: BUILD_DIR, WORK_DIR,
# EXAMPLE_DIR, GENERATOR, CXX_COMPILER.
set(prefix "${WORK_DIR}/prefix")
set(example_build "${WORK_DIR}/build")
set(output "${WORK_DIR}/output")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${output}")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run("install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(file include/ctsplines/vtkCloughTocherSplineFilter.h
             include/ctsplines/CTSplinesFiltersModule.h
             lib/cmake/CTSplines/CTSplinesConfig.cmake)
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "not installed: ${file}")
  endif()
endforeach()

# Only the scratch prefix may provide CTSplines: the build tree's own package is not searched.
run("configure the example" "${CMAKE_COMMAND}" -S "${EXAMPLE_DIR}" -B "${example_build}"
  -G "${GENERATOR}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" -DCMAKE_BUILD_TYPE=Release
  "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS "${example_build}/CMakeCache.txt" found REGEX "^CTSplines_DIR:")
if(NOT found MATCHES "${prefix}")
  message(FATAL_ERROR "CTSplines was not found in the install prefix: ${found}")
endif()
run("build the example" "${CMAKE_COMMAND}" --build "${example_build}")
run("run the example" "${example_build}/franke_spline" "${output}" 6 3)
message(STATUS "${run_output}")
# 6 x 6 grid: 72 triangles, 49 points; 216 Bezier triangles; 9 triangles each when tessellated.
foreach(line "input triangles 72" "input points 49" "bezier triangles 216"
             "tessellation triangles 1944")
  string(FIND "${run_output}" "${line}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "missing '${line}' in the example's output")
  endif()
endforeach()
foreach(file franke_spline.vtu franke_tessellation.vtp)
  if(NOT EXISTS "${output}/${file}")
    message(FATAL_ERROR "the example did not write ${file}")
  endif()
endforeach()
