#include "assets/yaml_util.hpp"

#include "base/files.hpp"
#include "facet/memory.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <new>
#include <set>

namespace facet::yaml {

namespace {

// What a node holds, for "expected X, got Y" messages.
std::string describe(const YAML::Node& node) {
    switch (node.Type()) {
        case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
        case YAML::NodeType::Sequence: return "a sequence of " + std::to_string(node.size());
        case YAML::NodeType::Map: return "a map";
        default: return "nothing";
    }
}

Error wrong_type(const Context& ctx, const YAML::Node& node, const std::string& expected) {
    return error(ctx, node, ErrorCode::wrong_type,
                 "expected " + expected + ", got " + describe(node));
}

bool is_plain_scalar(const YAML::Node& node) { return node.IsScalar() && node.Tag() != "!"; }

template <int N> glm::vec<N, float> as_vec(const Context& ctx, const YAML::Node& node) {
    as_numbers(ctx, node, N, N);  // N numbers
    glm::vec<N, float> v;
    for (int i = 0; i < N; ++i) v[i] = as<float>(ctx, node[i]);  // each a float
    return v;
}

std::string count_text(size_t min, size_t max) {
    if (min == max) return std::to_string(min) + (min == 1 ? " number" : " numbers");
    if (min + 1 == max) return std::to_string(min) + " or " + std::to_string(max) + " numbers";
    return std::to_string(min) + " to " + std::to_string(max) + " numbers";
}

}  // namespace

int line(const YAML::Node& node) { return node.Mark().line + 1; }
int column(const YAML::Node& node) { return node.Mark().column + 1; }

Error error(const Context& ctx, const YAML::Node& at, ErrorCode code, std::string detail) {
    return Error(code, std::move(detail), ctx.file, line(at), column(at));
}

Error relocated(const Error& inner, const std::string& file, int line, int column) {
    std::string detail;
    if (!inner.file().empty()) {
        detail = inner.file();
        for (int n : {inner.line(), inner.column()}) {  // a column only after a line
            if (n <= 0) break;
            detail.append(":").append(std::to_string(n));
        }
        if (!inner.detail().empty()) detail.append(": ");
    }
    detail.append(inner.detail());
    return Error(inner.code(), detail, file, line, column);
}

Error relocated(const Error& inner, const Context& ctx, const YAML::Node& at) {
    return relocated(inner, ctx.file, line(at), column(at));
}

namespace {

// What yaml-cpp holds for a parsed document, which is far more than its
// text: measured at 450 to 490 bytes a node (a flow list of 1.5 million
// one-digit numbers, 3 MB, took 673 MB; block lists and maps alike). The
// nodes are counted, from above, as the characters that can start one.
uint64_t parsed_bytes(std::string_view text) {
    const uint64_t nodes = uint64_t(std::count_if(text.begin(), text.end(), [](char c) {
        return c == ',' || c == '\n' || c == ':' || c == '[' || c == '{' || c == '-' || c == '?';
    }));
    return text.size() + (nodes + 1) * 512;
}

}  // namespace

YAML::Node load_file(const std::filesystem::path& path) {
    require_regular_file(path);
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw Error(ErrorCode::file_not_found, "cannot be read: " + ec.message(), path.string());
    require_within_budget(size, "the YAML file", path.string());
    std::string text(size_t(size), '\0');
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(text.data(), std::streamsize(size)))
        throw Error(ErrorCode::file_not_found, "cannot be read", path.string());
    return load_text(text, path.string());
}

YAML::Node load_text(const std::string& text, const std::string& origin) {
    require_within_budget(parsed_bytes(text),
                          "parsing " + std::to_string(text.size()) +
                              " bytes of YAML (yaml-cpp holds about 500 bytes a value; keep "
                              "large data such as meshes and long animations in mesh files)",
                          origin);
    try {
        return YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        throw Error(ErrorCode::yaml_syntax, e.msg, origin, e.mark.line + 1, e.mark.column + 1);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::over_budget, "out of memory while parsing it", origin);
    }
}

void check_map(const Context& ctx, const YAML::Node& node, std::string_view what) {
    if (!node.IsMap()) throw wrong_type(ctx, node, "a map for " + std::string(what));
    std::set<std::string> seen;
    for (const auto& entry : node) {
        const YAML::Node& key = entry.first;
        if (!key.IsScalar()) throw wrong_type(ctx, key, "a key of " + std::string(what));
        if (!seen.insert(key.Scalar()).second)
            throw error(ctx, key, ErrorCode::config_invalid,
                        "duplicate key '" + key.Scalar() + "'");
        if (entry.second.IsNull())  // reported at the key: an empty value has no good place
            throw error(ctx, key, ErrorCode::wrong_type, "'" + key.Scalar() + "' has no value");
    }
}

void check_map(const Context& ctx, const YAML::Node& node, std::string_view what,
               std::initializer_list<std::string_view> allowed) {
    check_map(ctx, node, what);
    for (const auto& entry : node) {
        const std::string& name = entry.first.Scalar();
        if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
        std::string expected;
        for (std::string_view a : allowed) {
            if (!expected.empty()) expected += ", ";
            expected += a;
        }
        throw error(ctx, entry.first, ErrorCode::unknown_key,
                    "'" + name + "' (expected one of: " + expected + ")");
    }
}

void check_sequence(const Context& ctx, const YAML::Node& node, std::string_view what) {
    if (!node.IsSequence()) throw wrong_type(ctx, node, "a sequence for " + std::string(what));
}

YAML::Node require(const Context& ctx, const YAML::Node& map, const std::string& key) {
    const YAML::Node node = map[key];
    if (!node) throw error(ctx, map, ErrorCode::missing_key, "'" + key + "'");
    return node;
}

std::optional<double> parse_number(const YAML::Node& node) {
    if (!is_plain_scalar(node)) return std::nullopt;
    std::string_view text = node.Scalar();
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        return std::nullopt;
    return value;
}

std::optional<bool> parse_bool(const YAML::Node& node) {
    if (!is_plain_scalar(node)) return std::nullopt;
    const std::string& text = node.Scalar();
    if (text == "true" || text == "True" || text == "TRUE") return true;
    if (text == "false" || text == "False" || text == "FALSE") return false;
    return std::nullopt;
}

bool is_integer_text(const std::string& scalar) {
    return scalar.find_first_of(".eE") == std::string::npos;
}

template <> double as<double>(const Context& ctx, const YAML::Node& node) {
    const std::optional<double> value = parse_number(node);
    if (!value) throw wrong_type(ctx, node, "a number");
    return *value;
}

template <> float as<float>(const Context& ctx, const YAML::Node& node) {
    const std::optional<double> value = parse_number(node);
    if (!value) throw wrong_type(ctx, node, "a number");
    if (std::abs(*value) > std::numeric_limits<float>::max())
        throw error(ctx, node, ErrorCode::out_of_range,
                    node.Scalar() + " is beyond the range of a float (3.4e38)");
    return static_cast<float>(*value);
}

template <> int as<int>(const Context& ctx, const YAML::Node& node) {
    const std::optional<double> value = parse_number(node);
    if (!value || !is_integer_text(node.Scalar()) ||
        std::abs(*value) > std::numeric_limits<int>::max())
        throw wrong_type(ctx, node, "an integer");
    return static_cast<int>(*value);
}

template <> bool as<bool>(const Context& ctx, const YAML::Node& node) {
    const std::optional<bool> value = parse_bool(node);
    if (!value) throw wrong_type(ctx, node, "true or false");
    return *value;
}

template <> std::string as<std::string>(const Context& ctx, const YAML::Node& node) {
    if (!node.IsScalar()) throw wrong_type(ctx, node, "a string");
    return node.Scalar();
}

template <> glm::vec2 as<glm::vec2>(const Context& ctx, const YAML::Node& node) {
    return as_vec<2>(ctx, node);
}
template <> glm::vec3 as<glm::vec3>(const Context& ctx, const YAML::Node& node) {
    return as_vec<3>(ctx, node);
}
template <> glm::vec4 as<glm::vec4>(const Context& ctx, const YAML::Node& node) {
    return as_vec<4>(ctx, node);
}

std::vector<double> as_numbers(const Context& ctx, const YAML::Node& node, size_t min, size_t max) {
    const std::string expected = "a sequence of " + count_text(min, max);
    if (!node.IsSequence() || node.size() < min || node.size() > max)
        throw wrong_type(ctx, node, expected);
    std::vector<double> numbers;
    for (const YAML::Node& item : node) {
        const std::optional<double> value = parse_number(item);
        if (!value) throw wrong_type(ctx, item, "a number in " + expected);
        numbers.push_back(*value);
    }
    return numbers;
}

}  // namespace facet::yaml
