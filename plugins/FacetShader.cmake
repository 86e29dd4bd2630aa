# facet_add_shader(NAME SOURCES src...)
#
# Builds the shader plugin NAME as a loadable module NAME.so in
# FACET_PLUGIN_OUTPUT_DIR (or the current binary folder if that is unset).
# The target is called facet_shader_NAME. It links only the SDK: a shader
# plugin never links the core. It is optimised (-O2) unless the project
# chooses a build type or builds with sanitizers (whose presets ask for -O1:
# AddressSanitizer with UndefinedBehaviorSanitizer at -O2 compiles a shader
# six times more slowly).
#
# On x86-64 the sources are compiled twice more, for the avx2 (x86-64-v3)
# and avx512 (x86-64-v4) paths, with FACET_SDK_ISA_avx2 or _avx512 set: there
# <facet/shader.hpp> gives only the shader's wide fragment loop, with the
# lane count that path's registers hold, and the descriptor points the
# host at it (facet_shader_desc.fragment_avx2, fragment_avx512). Compile
# definitions, options and include folders added to the target later apply
# to these builds too.
#
# facet_isa_objects(NAME ISA KEEP symbol LIKE target SOURCES src...
#                   [DEFINITIONS def...] OUTPUT var)
#
# Compiles SOURCES for instruction-set path ISA (portable, avx2 or avx512)
# with the compile settings of target LIKE, and links them into one
# relocatable object, `var`, in which every symbol but KEEP is local. The
# core builds its per-path kernels this way too. Without the last step the
# final link would keep one copy of each inline function the paths share
# (a std::min, a glm operator, compiled once with AVX-512 and once for
# SSE2) and a slower path could call the faster path's copy, which the CPU
# may not have.
#
# What runs when the library is loaded runs on every CPU, so these objects
# must have none of it: a namespace-scope object with a dynamic
# initialiser (a std::vector, a table filled by a function) would run its
# AVX-512 copy at dlopen on a CPU without AVX-512. The build fails on one
# (constexpr tables and function-local statics are fine). Sanitizer builds,
# which add constructors of their own, are exempt.

# Run as a script (cmake -P) by facet_isa_objects: fails if OBJECT has
# load-time constructors, unless OPTIONS ask for a sanitizer.
if(CMAKE_SCRIPT_MODE_FILE AND DEFINED FACET_CHECK_OBJECT)
  if(NOT OPTIONS MATCHES "-fsanitize")
    execute_process(COMMAND "${OBJDUMP}" -h "${FACET_CHECK_OBJECT}"
                    OUTPUT_VARIABLE sections RESULT_VARIABLE failed)
    if(failed)
      message(FATAL_ERROR "${OBJDUMP} -h ${FACET_CHECK_OBJECT} failed")
    endif()
    if(sections MATCHES "\\.(init_array|ctors)")
      message(FATAL_ERROR "${SOURCES}: the ${ISA} build has code that runs when the "
        "library is loaded (a namespace-scope object with a dynamic initialiser), "
        "which would run ${ISA} instructions on every CPU. Make it constexpr or a "
        "function-local static.")
    endif()
  endif()
  return()
endif()
set(FACET_SHADER_CMAKE "${CMAKE_CURRENT_LIST_FILE}")

# The paths beyond the baseline that this target architecture gets.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(FACET_WIDE_ISAS avx2 avx512)
  # A sanitizer or fuzzing build (facet's presets tsan, asan and fuzz) is for
  # running: it builds only the wide paths this CPU runs. Instrumenting code
  # that cannot run here finds nothing, and the default build compiles every
  # path.
  if((FACET_SANITIZE OR FACET_FUZZ) AND EXISTS /proc/cpuinfo)
    file(STRINGS /proc/cpuinfo cpu_flags REGEX "^flags" LIMIT_COUNT 1)
    foreach(flag avx512f avx512bw avx512cd avx512dq avx512vl)
      if(NOT cpu_flags MATCHES " ${flag}( |$)")
        list(REMOVE_ITEM FACET_WIDE_ISAS avx512)
      endif()
    endforeach()
    foreach(flag avx2 fma bmi2 f16c)
      if(NOT cpu_flags MATCHES " ${flag}( |$)")
        set(FACET_WIDE_ISAS "")
      endif()
    endforeach()
    # The sanitizer and fuzzing presets run the CPU's best path only
    # (FACET_SANITIZE_BEST_PATH): they build it and the portable one, and
    # not, on an AVX-512 CPU, the AVX2 path they would never run.
    if(FACET_SANITIZE_BEST_PATH AND FACET_WIDE_ISAS)
      list(GET FACET_WIDE_ISAS -1 best)  # avx512 after avx2
      set(FACET_WIDE_ISAS ${best})
    endif()
    message(STATUS "facet: sanitizer build of the paths this CPU runs: portable ${FACET_WIDE_ISAS}")
  endif()
  # The fuzz targets test loading and the core's kernels, ThreadSanitizer
  # the threads that share a frame, and AddressSanitizer the core's memory,
  # whatever path a shader runs: those builds' shaders run their portable
  # fragment functions only (the default build holds every shader's wide
  # builds to it, on every path).
  set(FACET_SHADER_ISAS ${FACET_WIDE_ISAS})
  if(FACET_FUZZ OR FACET_SANITIZE)
    set(FACET_SHADER_ISAS "")
  endif()
else()
  set(FACET_WIDE_ISAS "")
endif()

# Compiler flags of an instruction-set path. No path contracts a * b + c
# into a fused multiply-add, which rounds once where the portable path
# rounds twice: so every path computes the same floats, and draws the same
# image, bit for bit.
function(facet_isa_flags ISA OUT)
  if(ISA STREQUAL "avx2")
    set(${OUT} -march=x86-64-v3 -ffp-contract=off PARENT_SCOPE)
  elseif(ISA STREQUAL "avx512")
    set(${OUT} -march=x86-64-v4 -ffp-contract=off PARENT_SCOPE)
  elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
    # SSE2 even when the project's flags name a newer CPU.
    set(${OUT} -march=x86-64 -mtune=generic -ffp-contract=off PARENT_SCOPE)
  else()
    set(${OUT} -ffp-contract=off PARENT_SCOPE)
  endif()
endfunction()

# The relocatable link below resolves COMDAT groups (--force-group-allocation),
# which GNU ld does and LLVM's lld 14 (clang's CMAKE_LINKER) does not.
find_program(FACET_GNU_LD NAMES ld.bfd ld REQUIRED)

function(facet_isa_objects NAME ISA)
  cmake_parse_arguments(ARG "" "KEEP;LIKE;OUTPUT" "SOURCES;DEFINITIONS" ${ARGN})
  facet_isa_flags(${ISA} flags)
  add_library(${NAME} OBJECT ${ARG_SOURCES})
  # The path's flags last, so that they win over the target's own.
  target_compile_options(${NAME} PRIVATE
    $<TARGET_PROPERTY:${ARG_LIKE},COMPILE_OPTIONS> ${flags})
  target_compile_definitions(${NAME} PRIVATE ${ARG_DEFINITIONS}
    $<TARGET_PROPERTY:${ARG_LIKE},COMPILE_DEFINITIONS>)
  target_include_directories(${NAME} PRIVATE
    $<TARGET_PROPERTY:${ARG_LIKE},INCLUDE_DIRECTORIES>)
  target_compile_features(${NAME} PRIVATE cxx_std_20)
  set_target_properties(${NAME} PROPERTIES
    POSITION_INDEPENDENT_CODE ON
    C_VISIBILITY_PRESET hidden
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  set(object "${CMAKE_CURRENT_BINARY_DIR}/${NAME}.o")
  string(JOIN ", " sources ${ARG_SOURCES})  # one argument for the check below
  add_custom_command(OUTPUT "${object}"
    COMMAND "${FACET_GNU_LD}" -r --force-group-allocation -o "${object}.all"
            "$<TARGET_OBJECTS:${NAME}>"
    COMMAND "${CMAKE_OBJCOPY}" "--keep-global-symbol=${ARG_KEEP}" "${object}.all" "${object}.local"
    COMMAND "${CMAKE_COMMAND}" "-DFACET_CHECK_OBJECT=${object}.local" "-DOBJDUMP=${CMAKE_OBJDUMP}"
            "-DISA=${ISA}" "-DSOURCES=${sources}"
            "-DOPTIONS=${CMAKE_CXX_FLAGS} $<JOIN:$<TARGET_PROPERTY:${ARG_LIKE},COMPILE_OPTIONS>, >"
            -P "${FACET_SHADER_CMAKE}"
    COMMAND "${CMAKE_COMMAND}" -E rename "${object}.local" "${object}"
    DEPENDS ${NAME} "$<TARGET_OBJECTS:${NAME}>"
    COMMENT "Linking the ${ISA} objects of ${NAME}, all local but ${ARG_KEEP}"
    COMMAND_EXPAND_LISTS VERBATIM)
  set_source_files_properties("${object}" PROPERTIES EXTERNAL_OBJECT TRUE GENERATED TRUE)
  set(${ARG_OUTPUT} "${object}" PARENT_SCOPE)
endfunction()

function(facet_add_shader NAME)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "facet_add_shader(${NAME}): SOURCES is required")
  endif()
  set(target facet_shader_${NAME})
  facet_plugin_module(${target} ${NAME} ${ARG_SOURCES})
  foreach(isa IN LISTS FACET_SHADER_ISAS)
    facet_isa_objects(${target}_${isa} ${isa} KEEP facet_sdk_fragment_${isa} LIKE ${target}
                      SOURCES ${ARG_SOURCES} DEFINITIONS FACET_SDK_ISA_${isa}
                      OUTPUT object)
    target_sources(${target} PRIVATE "${object}")
  endforeach()
endfunction()

# facet_add_post(NAME SOURCES src...)
#
# Builds the screen pass NAME (<facet/post.hpp>, FACET_POST) as a loadable
# module NAME.so beside the shaders; the target is facet_post_NAME. A pass
# is built once: its loops are plain C++, which the compiler vectorises
# for the baseline instruction set, the same on every path.
function(facet_add_post NAME)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "facet_add_post(${NAME}): SOURCES is required")
  endif()
  facet_plugin_module(facet_post_${NAME} ${NAME} ${ARG_SOURCES})
endfunction()

# The loadable module `target` (NAME.so) from the sources that follow: the
# SDK, -O2 unless the project chose a build type (a plugin runs per pixel),
# its folder, visibility and link rules.
function(facet_plugin_module target NAME)
  add_library(${target} MODULE ${ARGN})
  target_link_libraries(${target} PRIVATE facet::sdk)
  if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES AND NOT FACET_SANITIZE)
    target_compile_options(${target} PRIVATE -O2)
  endif()
  if(DEFINED FACET_PLUGIN_OUTPUT_DIR)
    set(out_dir "${FACET_PLUGIN_OUTPUT_DIR}")
  else()
    set(out_dir "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME ${NAME}
    SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY "${out_dir}"
    C_VISIBILITY_PRESET hidden
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  # Refuse undefined symbols at link time: a plugin must be self-contained.
  target_link_options(${target} PRIVATE "LINKER:--no-undefined")
endfunction()
