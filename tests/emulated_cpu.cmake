# facet-render on an emulated CPU (qemu-x86_64 -cpu CPU), which raises an
# illegal-instruction fault for any instruction that CPU lacks:
#
#   cmake -DQEMU=... -DCPU=Opteron_G1 -DPATH_NAME=sse2 -DRENDER=facet-render
#         -DSCENE=scene.yaml -DOUT=dir -P emulated_cpu.cmake
#
# facet-render must pick PATH_NAME by itself, finish, and write the image
# that it writes natively, bit for bit (every path draws the same image).
# With FORCE=path it must instead refuse that path the CPU lacks, naming it.
cmake_minimum_required(VERSION 3.25)
foreach(var QEMU CPU RENDER SCENE OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "emulated_cpu.cmake: -D${var}=... is required")
  endif()
endforeach()
file(MAKE_DIRECTORY "${OUT}")
set(args "${SCENE}" --size 200x120)

if(DEFINED FORCE)
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env FACET_ISA=${FORCE} "${QEMU}" -cpu ${CPU} "${RENDER}" ${args}
            -o "${OUT}/forced.png"
    RESULT_VARIABLE status ERROR_VARIABLE log OUTPUT_VARIABLE log_out)
  if(status EQUAL 0 OR NOT log MATCHES "instruction set not available on this CPU: ${FORCE}")
    message(FATAL_ERROR "FACET_ISA=${FORCE} on ${CPU}: expected a refusal naming ${FORCE}, "
                        "got status ${status}:\n${log}")
  endif()
  return()
endif()

execute_process(COMMAND "${RENDER}" ${args} -o "${OUT}/native.png"
                RESULT_VARIABLE status ERROR_VARIABLE native_log)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "facet-render failed natively:\n${native_log}")
endif()
execute_process(COMMAND "${QEMU}" -cpu ${CPU} "${RENDER}" ${args} -o "${OUT}/emulated.png"
                RESULT_VARIABLE status ERROR_VARIABLE log)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "facet-render on an emulated ${CPU} failed (status ${status}):\n${log}")
endif()
if(NOT log MATCHES "\\] ${PATH_NAME} path on ")
  message(FATAL_ERROR "on an emulated ${CPU}, expected the ${PATH_NAME} path:\n${log}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT}/native.png" "${OUT}/emulated.png"
                RESULT_VARIABLE differ)
if(differ)
  message(FATAL_ERROR "the ${PATH_NAME} path on an emulated ${CPU} drew another image than "
                      "the native path (${OUT})")
endif()
