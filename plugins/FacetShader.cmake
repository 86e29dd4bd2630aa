# facet_add_shader(NAME SOURCES src...)
#
# Builds the shader plugin NAME as a loadable module NAME.so in
# FACET_PLUGIN_OUTPUT_DIR (or the current binary folder if that is unset).
# The target is called facet_shader_NAME. It links only the SDK: a shader
# plugin never links the core.
function(facet_add_shader NAME)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "facet_add_shader(${NAME}): SOURCES is required")
  endif()
  set(target facet_shader_${NAME})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE facet::sdk)
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
