# facet_add_shader(NAME SOURCES src...)
#
# Builds the shader plugin NAME as a loadable module NAME.so in
# FACET_PLUGIN_OUTPUT_DIR (or the current binary folder if that is unset).
# The target is called facet_shader_NAME. It links only the SDK: a shader
# plugin never links the core. It is optimised (-O2) unless the project
# chooses a build type.
#
# On x86-64 the sources are compiled twice more, for the avx2 (x86-64-v3)
# and avx512 (x86-64-v4) paths, with FACET_SDK_ISA set: there
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

# The paths beyond the baseline that this target architecture gets.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(FACET_WIDE_ISAS avx2 avx512)
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
  else()
    set(${OUT} -ffp-contract=off PARENT_SCOPE)
  endif()
endfunction()

function(facet_isa_objects NAME ISA)
  cmake_parse_arguments(ARG "" "KEEP;LIKE;OUTPUT" "SOURCES;DEFINITIONS" ${ARGN})
  facet_isa_flags(${ISA} flags)
  add_library(${NAME} OBJECT ${ARG_SOURCES})
  target_compile_options(${NAME} PRIVATE ${flags}
    $<TARGET_PROPERTY:${ARG_LIKE},COMPILE_OPTIONS>)
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
  add_custom_command(OUTPUT "${object}"
    COMMAND "${CMAKE_LINKER}" -r --force-group-allocation -o "${object}.all"
            "$<TARGET_OBJECTS:${NAME}>"
    COMMAND "${CMAKE_OBJCOPY}" "--keep-global-symbol=${ARG_KEEP}" "${object}.all" "${object}"
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
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE facet::sdk)
  if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
    target_compile_options(${target} PRIVATE -O2)  # a shader runs per pixel
  endif()
  foreach(isa IN LISTS FACET_WIDE_ISAS)
    facet_isa_objects(${target}_${isa} ${isa} KEEP facet_sdk_fragment_${isa} LIKE ${target}
                      SOURCES ${ARG_SOURCES} DEFINITIONS FACET_SDK_ISA_${isa}
                      OUTPUT object)
    target_sources(${target} PRIVATE "${object}")
  endforeach()
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
