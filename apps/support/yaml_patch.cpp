#include "facet/yaml_patch.hpp"

#include <facet/error.hpp>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

namespace facet {

namespace {

bool is_flow(const YAML::Node& n) {
    return (n.IsMap() || n.IsSequence()) && n.Style() == YAML::EmitterStyle::Flow;
}

// The end of a comment-free line from `at`: the newline or the end.
size_t line_end(const std::string& t, size_t at) {
    const size_t nl = t.find('\n', at);
    return nl == std::string::npos ? t.size() : nl;
}

// Where a plain scalar that starts at `at` ends: before a comment (" #"),
// the line's end, or (inside a flow collection) a ',', ']' or '}'; trailing
// blanks excluded.
size_t plain_end(const std::string& t, size_t at, bool in_flow) {
    size_t i = at;
    for (; i < t.size() && t[i] != '\n'; ++i) {
        if (t[i] == '#' && i > at && (t[i - 1] == ' ' || t[i - 1] == '\t')) break;
        if (in_flow && (t[i] == ',' || t[i] == ']' || t[i] == '}')) break;
    }
    while (i > at && (t[i - 1] == ' ' || t[i - 1] == '\t' || t[i - 1] == '\r')) --i;
    return i;
}

// One past the bracket that closes the one at `open`, skipping quoted
// scalars (a quote opens one only where a scalar starts: after a bracket, a
// comma or a colon) and comments.
size_t matching_end(const std::string& t, size_t open) {
    int depth = 0;
    char before = '\n';  // the last character that is not a blank
    for (size_t i = open; i < t.size(); ++i) {
        const char c = t[i];
        if ((c == '"' || c == '\'') && (before == '[' || before == '{' || before == ',' ||
                                         before == ':' || before == '\n')) {
            for (++i; i < t.size() && t[i] != c; ++i)
                if (c == '"' && t[i] == '\\') ++i;
        } else if (c == '[' || c == '{') {
            ++depth;
        } else if (c == ']' || c == '}') {
            if (--depth == 0) return i + 1;
        } else if (c == '#' && (t[i - 1] == ' ' || t[i - 1] == '\t' || t[i - 1] == '\n')) {
            i = line_end(t, i) - 1;
            continue;  // `before` stays what it was
        }
        if (c != ' ' && c != '\t' && c != '\r') before = c;
    }
    return t.size();
}

// One past the last character of `n`'s text (not counting a comment after it).
size_t node_end(const std::string& t, const YAML::Node& n, bool in_flow) {
    const size_t at = n.Mark().pos;
    if (is_flow(n)) return matching_end(t, at);
    if (n.IsMap() || n.IsSequence()) {  // block: where its last item ends
        YAML::Node last;
        bool any = false;
        for (auto it = n.begin(); it != n.end(); ++it, any = true) last.reset(n.IsMap() ? it->second : *it);
        return any ? node_end(t, last, false) : at;
    }
    if (at < t.size() && (t[at] == '|' || t[at] == '>'))
        throw Error(ErrorCode::config_invalid,
                    "a block scalar (| or >) at line " + std::to_string(n.Mark().line + 1) +
                        " is not edited in place; edit it by hand");
    if (at < t.size() && (t[at] == '"' || t[at] == '\'')) {
        const char q = t[at];
        for (size_t i = at + 1; i < t.size(); ++i) {
            if (q == '"' && t[i] == '\\') ++i;
            else if (t[i] == q && !(q == '\'' && i + 1 < t.size() && t[i + 1] == '\'')) return i + 1;
            else if (q == '\'' && t[i] == q) ++i;  // '' inside single quotes
        }
        return t.size();
    }
    return plain_end(t, at, in_flow);
}

[[noreturn]] void fail(const std::string& file, const YamlPath& path, const std::string& why) {
    throw Error(ErrorCode::config_invalid, "cannot set " + to_string(path) + ": " + why, file);
}

// Whether a document uses anchors or aliases (&name, *name). yaml-cpp gives
// an alias's node the anchor's position, so text found through it would be
// the anchor's: such a file is not edited in place.
class AnchorFinder : public YAML::EventHandler {
public:
    bool found = false;
    void OnDocumentStart(const YAML::Mark&) override {}
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t a) override { found |= a != 0; }
    void OnAlias(const YAML::Mark&, YAML::anchor_t) override { found = true; }
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t a,
                  const std::string&) override {
        found |= a != 0;
    }
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t a,
                         YAML::EmitterStyle::value) override {
        found |= a != 0;
    }
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t a,
                    YAML::EmitterStyle::value) override {
        found |= a != 0;
    }
    void OnMapEnd() override {}
};

bool uses_anchors(const std::string& text) {
    std::istringstream in(text);
    YAML::Parser parser(in);
    AnchorFinder finder;
    while (parser.HandleNextDocument(finder)) {}
    return finder.found;
}

// `rest` of a path as the value of a new key: "k:\n  k2: value" (block) or
// "k: {k2: value}" (inside a flow mapping). Empty when the rest names a
// sequence item (which would not exist yet).
std::string new_entry(const YamlPath& rest, size_t from, const std::string& value, bool flow,
                      int indent, const std::string& newline) {
    for (size_t k = from; k < rest.size(); ++k)
        if (!std::holds_alternative<std::string>(rest[k])) return {};
    const std::string& key = std::get<std::string>(rest[from]);
    if (from + 1 == rest.size()) return key + ": " + value;
    if (flow) return key + ": {" + new_entry(rest, from + 1, value, true, 0, newline) + "}";
    return key + ":" + newline + std::string(size_t(indent + 2), ' ') +
           new_entry(rest, from + 1, value, false, indent + 2, newline);
}

}  // namespace

std::string to_string(const YamlPath& path) {
    std::string out;
    for (const auto& part : path) {
        if (const auto* key = std::get_if<std::string>(&part)) {
            if (!out.empty()) out += '.';
            out += *key;
        } else {
            out += '[';
            out += std::to_string(std::get<size_t>(part));
            out += ']';
        }
    }
    return out.empty() ? "(the document)" : out;
}

namespace {

// yaml_set() on a text with no byte-order mark; `newline` is the file's.
std::string set_in(const std::string& text, const YamlPath& path, const std::string& value,
                   const std::string& file, const std::string& newline) {
    YAML::Node node;
    try {
        node = YAML::Load(text);
        if (uses_anchors(text))
            fail(file, path, "the file uses YAML anchors or aliases (&name, *name), which are "
                             "not edited in place; edit it by hand");
    } catch (const YAML::Exception& e) {
        throw Error(ErrorCode::config_invalid, e.msg, file, e.mark.line + 1, e.mark.column + 1);
    }
    if (path.empty()) fail(file, path, "no key given");
    bool in_flow = false;
    for (size_t k = 0; k < path.size(); ++k) {
        if (const auto* index = std::get_if<size_t>(&path[k])) {
            if (!node.IsSequence() || *index >= node.size())
                fail(file, path, "no item " + std::to_string(*index) + " there");
            in_flow = in_flow || is_flow(node);
            node.reset(node[*index]);
            continue;
        }
        const std::string& key = std::get<std::string>(path[k]);
        if (!node.IsMap()) fail(file, path, "not a mapping at " + key);
        YAML::Node key_node, value_node;
        bool found = false;
        for (auto it = node.begin(); it != node.end(); ++it)
            if (it->first.IsScalar() && it->first.Scalar() == key) {
                key_node.reset(it->first);
                value_node.reset(it->second);
                found = true;
            }
        const bool flow_map = in_flow || is_flow(node);
        if (!found) {  // a new key in this mapping
            YAML::Node first_key, last_key, last_value;
            bool any = false;
            for (auto it = node.begin(); it != node.end(); ++it) {
                if (!any) first_key.reset(it->first);
                last_key.reset(it->first);
                last_value.reset(it->second);
                any = true;
            }
            if (is_flow(node)) {
                const size_t close = matching_end(text, node.Mark().pos) - 1;
                const std::string entry = new_entry(path, k, value, true, 0, newline);
                if (entry.empty()) fail(file, path, "the item does not exist");
                return text.substr(0, close) + (node.size() ? ", " : "") + entry + text.substr(close);
            }
            if (!any) fail(file, path, "an empty mapping");
            const int indent = first_key.Mark().column;
            const std::string entry = new_entry(path, k, value, false, indent, newline);
            if (entry.empty()) fail(file, path, "the item does not exist");
            size_t at = line_end(text, last_value.IsNull() ? last_key.Mark().pos
                                                           : node_end(text, last_value, false));
            if (at > 0 && at <= text.size() && text[at - 1] == '\r') --at;  // before a CRLF
            std::string out = text.substr(0, at) + newline + std::string(size_t(indent), ' ') +
                              entry + text.substr(at);
            if (at == text.size()) out += newline;
            return out;
        }
        if (k + 1 < path.size() && value_node.IsNull()) {  // "key:" with nothing under it yet
            const size_t colon = text.find(':', key_node.Mark().pos);
            const size_t end = plain_end(text, colon + 1, flow_map);
            const int indent = key_node.Mark().column;
            const std::string rest =
                new_entry(path, k + 1, value, flow_map, flow_map ? 0 : indent + 2, newline);
            if (rest.empty()) fail(file, path, "the item does not exist");
            const std::string entry = flow_map ? " {" + rest + "}"
                                               : newline + std::string(size_t(indent + 2), ' ') + rest;
            return text.substr(0, colon + 1) + entry + text.substr(end);
        }
        in_flow = flow_map;
        if (k + 1 == path.size()) {  // replace the value
            if (value_node.IsNull()) {
                const size_t colon = text.find(':', key_node.Mark().pos);
                const size_t end = plain_end(text, colon + 1, flow_map);
                return text.substr(0, colon + 1) + " " + value + text.substr(end);
            }
            const size_t from = value_node.Mark().pos;
            return text.substr(0, from) + value + text.substr(node_end(text, value_node, in_flow));
        }
        node.reset(value_node);
    }
    // The path ended on a sequence item: replace it.
    const size_t from = node.Mark().pos;
    return text.substr(0, from) + value + text.substr(node_end(text, node, in_flow));
}

}  // namespace

std::string yaml_set(const std::string& text, const YamlPath& path, const std::string& value,
                     const std::string& file) {
    // yaml-cpp's positions do not count a UTF-8 byte-order mark.
    static const std::string kBom = "\xEF\xBB\xBF";
    const bool bom = text.compare(0, kBom.size(), kBom) == 0;
    const std::string body = bom ? text.substr(kBom.size()) : text;
    const std::string newline = body.find("\r\n") != std::string::npos ? "\r\n" : "\n";
    return (bom ? kBom : "") + set_in(body, path, value, file, newline);
}

std::string yaml_string(const std::string& s) {
    const bool plain =
        !s.empty() && s.find_first_of(":#,[]{}&*!|>'\"%@`\\\t\r\n") == std::string::npos &&
        s.front() != ' ' && s.back() != ' ' && s.front() != '-' && s.front() != '?' && [&] {
            std::string lower = s;  // the words YAML reads as null or a boolean, in any case
            for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
            return lower != "null" && lower != "true" && lower != "false" && lower != "~" &&
                   lower != "yes" && lower != "no" && lower != "on" && lower != "off";
        }();
    if (plain) return s;
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (c == '\n') out += "\\n";
        else if (c == '\t') out += "\\t";
        else if (c == '\r') out += "\\r";
        else out += c;
    }
    return out + "\"";
}

std::string yaml_number(float v) {
    if (!std::isfinite(v)) throw Error(ErrorCode::out_of_range, "not a finite number");
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, v);
    return std::string(text, r.ptr);
}

std::string yaml_sequence(const float* v, int n) {
    std::string out = "[";
    for (int i = 0; i < n; ++i) out += (i ? ", " : "") + yaml_number(v[i]);
    return out + "]";
}

}  // namespace facet
