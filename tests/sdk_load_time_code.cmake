# A shader with code that runs when its library is loaded (a namespace-scope
# object with a dynamic initialiser) must not build: facet_add_shader's AVX2
# and AVX-512 copies of it would run at dlopen on any CPU
# (plugins/FacetShader.cmake). Installs the SDK from BUILD, starts a shader
# project with facet-new-shader, adds such an object, and expects the build
# to stop with the message that says so.
#
#   cmake -DBUILD=<facet build> -DOUT=<dir> -P sdk_load_time_code.cmake
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "sdk_load_time_code.cmake: -D${var}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${OUT}/sdk"
                OUTPUT_QUIET COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND "${OUT}/sdk/bin/facet-new-shader" probe "${OUT}/shaders"
                OUTPUT_QUIET COMMAND_ERROR_IS_FATAL ANY)
set(project "${OUT}/shaders/probe")
file(APPEND "${project}/probe.cpp"
     "\n#include <vector>\nstatic const std::vector<float> load_time_table = {1.0f, 2.0f};\n")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${project}" -B "${project}/build"
                        "-DCMAKE_PREFIX_PATH=${OUT}/sdk"
                OUTPUT_QUIET COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${project}/build"
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE errors)
if(status EQUAL 0)
  message(FATAL_ERROR "a shader with a load-time constructor built")
endif()
string(REGEX REPLACE "[ \n]+" " " said "${output} ${errors}")
if(NOT said MATCHES "probe.cpp: the avx(2|512) build has code that runs when the library is loaded")
  message(FATAL_ERROR "the build failed, but not with the load-time code message:\n${output}\n${errors}")
endif()
message(STATUS "refused: ${CMAKE_MATCH_0}")
