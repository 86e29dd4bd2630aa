// facet errors: one table, one exception type.
//
// Every error the core reports for bad input (configs, plugins, meshes,
// textures) has an id in FACET_ERRORS. Code and tests test the id; the text
// is for people. An Error carries the file, line and column where it has them
// and formats as "file:line:column: message".
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace facet {

#define FACET_ERRORS(X)                                                      \
    X(file_not_found, "file not found")                                      \
    X(not_a_file, "not a regular file")                                      \
    X(yaml_syntax, "YAML syntax error")                                      \
    X(config_invalid, "invalid configuration")                               \
    X(unknown_key, "unknown key")                                            \
    X(missing_key, "missing key")                                            \
    X(wrong_type, "wrong type")                                              \
    X(out_of_range, "value out of range")                                    \
    X(unknown_shader, "unknown shader")                                      \
    X(plugin_load_failed, "plugin failed to load")                           \
    X(plugin_no_entry, "plugin has no entry point")                          \
    X(plugin_abi_mismatch, "plugin ABI version mismatch")                    \
    X(plugin_struct_size, "plugin descriptor size mismatch")                 \
    X(plugin_invalid, "plugin descriptor is invalid")                        \
    X(param_unknown, "unknown material parameter")                           \
    X(param_type, "material parameter has the wrong type")                   \
    X(param_range, "material parameter out of range")                        \
    X(mesh_load_failed, "mesh failed to load")                               \
    X(mesh_invalid, "mesh is invalid")                                       \
    X(texture_load_failed, "texture failed to load")                         \
    X(output_failed, "could not write output")                               \
    X(display_failed, "could not open a window")                             \
    X(isa_unavailable, "instruction set not available on this CPU")          \
    X(interrupted, "interrupted")                                            \
    X(over_budget, "over the memory budget")                                 \
    X(plugin_stalled, "a plugin call did not return")

enum class ErrorCode {
#define FACET_ERROR_ENUM(id, text) id,
    FACET_ERRORS(FACET_ERROR_ENUM)
#undef FACET_ERROR_ENUM
};

// The fixed text of an error id.
std::string_view error_text(ErrorCode code);
// The id as a string ("unknown_shader"), for logs and tests.
std::string_view error_name(ErrorCode code);

class Error : public std::runtime_error {
public:
    // line and column are 1-based; 0 means "not known".
    Error(ErrorCode code, std::string detail, std::string file = {}, int line = 0,
          int column = 0);

    ErrorCode code() const { return code_; }
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    int column() const { return column_; }
    const std::string& detail() const { return detail_; }

private:
    ErrorCode code_;
    std::string detail_;
    std::string file_;
    int line_;
    int column_;
};

}  // namespace facet
