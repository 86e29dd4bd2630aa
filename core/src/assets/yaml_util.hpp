// Strict YAML reading for configs (private to the core).
//
// Every reader takes a Context (the file being read) and the node it reads,
// and throws facet::Error at that node's file:line:column (1-based) when the
// value has the wrong shape. Nodes are only read, never modified: keep them
// `const YAML::Node`, because yaml-cpp's non-const operator[] inserts keys.
#pragma once

#include "facet/error.hpp"

#include <yaml-cpp/yaml.h>
#include <glm/glm.hpp>

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace facet::yaml {

struct Context {
    std::string file;  // as the user named it, for messages
};

// 1-based position of `node`; 0 when yaml-cpp has none.
int line(const YAML::Node& node);
int column(const YAML::Node& node);

// Error(code, detail) at `at`.
Error error(const Context& ctx, const YAML::Node& at, ErrorCode code, std::string detail);

// `inner` reported again at a new place, keeping its code; its own place
// moves into the detail: "scene.yaml:12:11: mesh failed to load: x.obj: why".
Error relocated(const Error& inner, const std::string& file, int line, int column);
Error relocated(const Error& inner, const Context& ctx, const YAML::Node& at);

// Parses the first document of `path`.
// Throws Error(file_not_found | yaml_syntax).
YAML::Node load_file(const std::filesystem::path& path);
// Parses the first document of `text`; errors name `origin`.
// Throws Error(yaml_syntax | over_budget).
YAML::Node load_text(const std::string& text, const std::string& origin);

// Checks that `node` is a map with scalar keys, each once, each with a
// value. `what` names the map in messages ("camera"). Throws
// Error(wrong_type | config_invalid).
void check_map(const Context& ctx, const YAML::Node& node, std::string_view what);
// The same, and every key is in `allowed`; throws Error(unknown_key) if not.
void check_map(const Context& ctx, const YAML::Node& node, std::string_view what,
               std::initializer_list<std::string_view> allowed);

// Throws error(ctx, at, code, detail) unless `ok`.
inline void ensure(bool ok, const Context& ctx, const YAML::Node& at, ErrorCode code,
                   const std::string& detail) {
    if (!ok) throw error(ctx, at, code, detail);
}

// map[key] if present, else the map: where to report a value's problem.
inline YAML::Node where(const YAML::Node& map, const std::string& key) {
    const YAML::Node value = map[key];
    return value ? value : map;
}

// Checks that `node` is a sequence; throws Error(wrong_type) if not.
void check_sequence(const Context& ctx, const YAML::Node& node, std::string_view what);

// map[key]; throws Error(missing_key) at the map if it is absent.
YAML::Node require(const Context& ctx, const YAML::Node& map, const std::string& key);

// Plain scalars as values. A quoted scalar is always a string.
std::optional<double> parse_number(const YAML::Node& node);  // finite numbers only
std::optional<bool> parse_bool(const YAML::Node& node);      // true / false
bool is_integer_text(const std::string& scalar);             // no '.', 'e' or 'E'

// Typed reads; throw Error(wrong_type) saying what was expected.
template <class T> T as(const Context& ctx, const YAML::Node& node);
template <> float as<float>(const Context& ctx, const YAML::Node& node);
template <> double as<double>(const Context& ctx, const YAML::Node& node);  // times
template <> int as<int>(const Context& ctx, const YAML::Node& node);
template <> bool as<bool>(const Context& ctx, const YAML::Node& node);
template <> std::string as<std::string>(const Context& ctx, const YAML::Node& node);
template <> glm::vec2 as<glm::vec2>(const Context& ctx, const YAML::Node& node);
template <> glm::vec3 as<glm::vec3>(const Context& ctx, const YAML::Node& node);
template <> glm::vec4 as<glm::vec4>(const Context& ctx, const YAML::Node& node);

// A sequence of `min`..`max` numbers.
std::vector<double> as_numbers(const Context& ctx, const YAML::Node& node, size_t min, size_t max);

// Sets `out` from map[key] if the key is present.
template <class T>
void read(const Context& ctx, const YAML::Node& map, const std::string& key, T& out) {
    if (const YAML::Node node = map[key]) out = as<T>(ctx, node);
}

// One of a fixed set of names; throws Error(config_invalid) listing them.
template <class E>
E as_enum(const Context& ctx, const YAML::Node& node,
          std::initializer_list<std::pair<std::string_view, E>> names) {
    const std::string text = as<std::string>(ctx, node);
    std::string expected;
    for (const auto& [name, value] : names) {
        if (name == text) return value;
        if (!expected.empty()) expected += ", ";
        expected += name;
    }
    throw error(ctx, node, ErrorCode::config_invalid,
                "'" + text + "' (expected one of: " + expected + ")");
}

}  // namespace facet::yaml
