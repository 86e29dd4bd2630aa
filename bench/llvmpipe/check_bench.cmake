# CTest facet-bench.llvmpipe: runs facet-bench --llvmpipe on the small scene
# and checks what it did, so that the test fails on a non-zero exit (a
# worker failed), on missing or unexpected llvmpipe columns, on more
# than MAX_PIXELS pixels of coverage difference in any row, and on a row
# compared with llvmpipe that does not say facet drew it without the
# scene's shadows, as llvmpipe does (or a row not compared that does).
#
#     cmake -DBENCH=path/to/facet-bench -DMAX_PIXELS=2 -P check_bench.cmake
#
# Writes llvmpipe.csv and llvmpipe.json in the working directory.
cmake_minimum_required(VERSION 3.25)  # CMP0007: empty CSV fields stay list elements

foreach(var BENCH MAX_PIXELS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_bench.cmake: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE llvmpipe.csv llvmpipe.json)
execute_process(
  COMMAND ${BENCH} --llvmpipe --scene small --size 160x90 --shader unlit --shader phong
          --shader lit --threads 1 --threads 2 --runs 1 --csv llvmpipe.csv --json llvmpipe.json
  RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "facet-bench --llvmpipe failed: ${status}")
endif()

file(STRINGS llvmpipe.csv lines)
list(POP_FRONT lines header)
string(REPLACE "," ";" header "${header}")
foreach(column note shader isa threads llvmpipe_median_ms coverage_diff_pixels)
  list(FIND header ${column} ${column}_at)
  if(${column}_at LESS 0)
    message(FATAL_ERROR "llvmpipe.csv has no column ${column}")
  endif()
endforeach()

set(rows 0)
foreach(line IN LISTS lines)
  string(REPLACE "," ";" fields "${line}")
  list(GET fields ${shader_at} shader)
  list(GET fields ${threads_at} threads)
  list(GET fields ${isa_at} isa)
  if(NOT isa MATCHES "^(sse2|avx2|avx512|neon|portable)$")
    message(FATAL_ERROR "a row names no instruction-set path: '${isa}'")
  endif()
  list(APPEND paths ${isa})
  list(GET fields ${llvmpipe_median_ms_at} ms)
  list(GET fields ${coverage_diff_pixels_at} pixels)
  list(GET fields ${note_at} note)
  set(row "${shader} at ${threads} threads")
  # Rows compared with llvmpipe are drawn without the scene's shadows, as
  # llvmpipe draws them; the others (lit) with them.
  if(shader STREQUAL "lit")
    if(NOT ms STREQUAL "")
      message(FATAL_ERROR "${row}: llvmpipe columns where llvmpipe has no shader")
    endif()
    if(note MATCHES "no shadows")
      message(FATAL_ERROR "${row}: drawn without shadows, though not compared ('${note}')")
    endif()
  elseif(NOT note MATCHES "no shadows \\(llvmpipe draws none\\)")
    message(FATAL_ERROR "${row}: drawn with shadows, which llvmpipe does not draw ('${note}')")
  elseif(ms STREQUAL "" OR NOT ms GREATER 0)
    message(FATAL_ERROR "${row}: no llvmpipe time ('${ms}')")
  elseif(NOT pixels MATCHES "^[0-9]+$" OR pixels GREATER MAX_PIXELS)
    message(FATAL_ERROR "${row}: ${pixels} pixels of coverage difference "
                        "(at most ${MAX_PIXELS})")
  endif()
  math(EXPR rows "${rows} + 1")
endforeach()
# Each path this CPU has measures every configuration.
list(REMOVE_DUPLICATES paths)
list(LENGTH paths path_count)
math(EXPR expected "6 * ${path_count}")
if(NOT rows EQUAL expected)
  message(FATAL_ERROR "llvmpipe.csv has ${rows} rows, not ${expected} "
                      "(3 shaders x 2 thread counts x ${path_count} paths)")
endif()
message(STATUS "llvmpipe.csv: ${rows} rows as expected")
