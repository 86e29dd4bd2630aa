// Setting values in a YAML file's text, keeping the rest of it as written.
//
// The viewer's editor saves through this: a scene or material file gets the
// values changed in the editor, and every other byte stays: key order,
// comments, blank lines, quoting, and the flow or block style of what was
// not changed. A key the file lacks is added after its mapping's last key,
// indented as its siblings (or appended inside a flow mapping's braces).
//
// A value is YAML flow text, as yaml_number() and yaml_sequence() write it:
// "0.5", "[1, 0.2, 0.2]", "{file: a.png, filter: nearest}". It replaces the
// whole old value, whatever its form (a block sequence becomes a flow one).
#pragma once

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

namespace facet {

// Keys of mappings and indices of sequences, from the document's root:
// {"lights", 1, "intensity"}.
using YamlPath = std::vector<std::variant<std::string, size_t>>;

// "lights[1].intensity".
std::string to_string(const YamlPath& path);

// `text` with the value at `path` set to `value`. Missing mappings on the
// way are created; a missing sequence item, or a path through a scalar, is
// an Error (config_invalid) naming `file` and the path, as is text that is
// not YAML, a file with anchors or aliases, and a block scalar (| or >) in
// the way. A byte-order mark and CRLF line ends are kept.
std::string yaml_set(const std::string& text, const YamlPath& path, const std::string& value,
                     const std::string& file = "<text>");

// The shortest text that reads back as the same float ("0.1", "3", "1e-07").
// Throws Error (out_of_range) for an infinity or a NaN, which a facet file
// may not hold.
std::string yaml_number(float v);
// `s` as a YAML scalar: as it is when it reads back as the same string,
// else double-quoted ("wood, dark.png").
std::string yaml_string(const std::string& s);
// "[a, b, c]".
std::string yaml_sequence(const float* v, int n);

}  // namespace facet
