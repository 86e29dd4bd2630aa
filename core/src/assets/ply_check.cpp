#include "assets/ply_check.hpp"

#include "facet/error.hpp"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace facet {

namespace {

constexpr int kMaxHeaderLines = 10000;
constexpr uint64_t kMaxCount = uint64_t(1) << 32;

enum class Format { ascii, binary_le, binary_be };

struct Property {
    int size = 0;          // bytes of a scalar, or of each list item
    int count_size = 0;    // bytes of a list's count; 0 for a scalar
    bool indices = false;  // a face's vertex_indices (or vertex_index) list
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
    int line = 0;  // of its header line
};

struct Header {
    Format format = Format::ascii;
    std::vector<Element> elements;
};

[[noreturn]] void ply_fail(const std::filesystem::path& path, const std::string& why, int line = 0) {
    throw Error(ErrorCode::mesh_load_failed, "malformed PLY: " + why, path.string(), line);
}

int type_size(const std::string& t) {
    static const std::pair<const char*, int> types[] = {
        {"char", 1},   {"uchar", 1},  {"int8", 1},   {"uint8", 1},   {"short", 2},
        {"ushort", 2}, {"int16", 2},  {"uint16", 2}, {"int", 4},     {"uint", 4},
        {"int32", 4},  {"uint32", 4}, {"float", 4},  {"float32", 4}, {"double", 8},
        {"float64", 8}};
    for (const auto& [name, size] : types)
        if (t == name) return size;
    return 0;
}

Property parse_property(std::istringstream& in, const std::filesystem::path& path, int line) {
    std::string type, count_type, item_type, name;
    in >> type;
    Property p;
    if (type == "list") {
        in >> count_type >> item_type >> name;
        p.count_size = type_size(count_type);
        p.size = type_size(item_type);
        if (!p.count_size || count_type == "float" || count_type == "double" || !p.size)
            ply_fail(path, "bad list property types '" + count_type + " " + item_type + "'", line);
    } else {
        in >> name;
        p.size = type_size(type);
        if (!p.size) ply_fail(path, "unknown property type '" + type + "'", line);
    }
    if (name.empty()) ply_fail(path, "property without a name", line);
    p.indices = p.count_size && (name == "vertex_indices" || name == "vertex_index");
    return p;
}

void parse_header_line(const std::string& text, Header& h, const std::filesystem::path& path,
                       int line) {
    std::istringstream in(text);
    std::string word;
    in >> word;
    if (word == "comment" || word == "obj_info" || word.empty()) return;
    if (word == "format") {
        std::string f;
        in >> f;
        if (f == "ascii") h.format = Format::ascii;
        else if (f == "binary_little_endian") h.format = Format::binary_le;
        else if (f == "binary_big_endian") h.format = Format::binary_be;
        else ply_fail(path, "unknown format '" + f + "'", line);
    } else if (word == "element") {
        Element e;
        std::string count;
        in >> e.name >> count;
        if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos ||
            count.size() > 10 || std::stoull(count) > kMaxCount)
            ply_fail(path, "element '" + e.name + "' has no valid count ('" + count + "')", line);
        e.count = std::stoull(count);
        e.line = line;
        h.elements.push_back(e);
    } else if (word == "property") {
        if (h.elements.empty()) ply_fail(path, "property before any element", line);
        h.elements.back().properties.push_back(parse_property(in, path, line));
    } else {
        ply_fail(path, "unexpected header line '" + text + "'", line);
    }
}

Header parse_header(std::istream& in, const std::filesystem::path& path) {
    Header h;
    std::string text;
    std::getline(in, text);
    if (text != "ply" && text != "ply\r") ply_fail(path, "missing 'ply' magic", 1);
    for (int line = 2; line <= kMaxHeaderLines; ++line) {
        if (!std::getline(in, text)) ply_fail(path, "header has no end_header", line);
        if (!text.empty() && text.back() == '\r') text.pop_back();
        if (text == "end_header") {
            // Entries without properties take no bytes, so the file's size
            // does not bound their count, and assimp 5.2 steps through each.
            for (const Element& e : h.elements)
                if (e.properties.empty() && e.count > 0)
                    ply_fail(path, "element '" + e.name + "' has " + std::to_string(e.count) +
                                   " entries but no properties", e.line);
            return h;
        }
        parse_header_line(text, h, path, line);
    }
    ply_fail(path, "header longer than " + std::to_string(kMaxHeaderLines) + " lines");
}

// A face of fewer than three vertices is no polygon (points and lines are
// PLY's "edge" elements), and assimp 5.2's triangulation aborts on one.
void check_list(uint64_t count, const Element& e, const Property& p, uint64_t i,
                const std::filesystem::path& path) {
    if (e.name != "face" || (count >= 3 && p.indices) || (count > 0 && !p.indices)) return;
    const std::string what = !p.indices ? " entries in a list"
                             : count == 1 ? " vertex index; a face needs at least 3"
                                          : " vertex indices; a face needs at least 3";
    ply_fail(path, "face " + std::to_string(i) + " has " + std::to_string(count) + what);
}

uint64_t read_count(std::istream& in, uint64_t pos, int size, bool big_endian) {
    unsigned char b[8] = {};
    in.seekg(std::streamoff(pos));
    in.read(reinterpret_cast<char*>(b), size);
    uint64_t v = 0;
    for (int i = 0; i < size; ++i) v |= uint64_t(b[big_endian ? size - 1 - i : i]) << (8 * i);
    return v;
}

// Walks the body by byte counts, reading only list counts, and checks that
// every element fits in the file.
void walk_binary(std::istream& in, const Header& h, const std::filesystem::path& path) {
    const uint64_t size = std::filesystem::file_size(path);
    uint64_t pos = uint64_t(in.tellg());
    const bool big = h.format == Format::binary_be;
    for (const Element& e : h.elements)
        for (uint64_t i = 0; i < e.count && !e.properties.empty(); ++i)
            for (const Property& p : e.properties) {
                uint64_t bytes = uint64_t(p.size);
                if (p.count_size && pos + p.count_size <= size) {
                    const uint64_t count = read_count(in, pos, p.count_size, big);
                    check_list(count, e, p, i, path);
                    bytes *= count;
                    pos += uint64_t(p.count_size);
                }
                pos += bytes;
                if (pos > size)
                    ply_fail(path, "file ends inside element '" + e.name + "' " +
                                   std::to_string(i) + " of " + std::to_string(e.count));
            }
}

void walk_ascii(std::istream& in, const Header& h, const std::filesystem::path& path) {
    std::string token;
    for (const Element& e : h.elements)
        for (uint64_t i = 0; i < e.count && !e.properties.empty(); ++i)
            for (const Property& p : e.properties) {
                uint64_t tokens = 1;
                if (p.count_size) {
                    if (!(in >> token) || token.empty() || token.size() > 10 ||
                        token.find_first_not_of("0123456789") != std::string::npos ||
                        std::stoull(token) > kMaxCount)
                        ply_fail(path, "bad list count in element '" + e.name + "' " + std::to_string(i));
                    tokens = std::stoull(token);
                    check_list(tokens, e, p, i, path);
                }
                for (uint64_t t = 0; t < tokens; ++t)
                    if (!(in >> token))
                        ply_fail(path, "file ends inside element '" + e.name + "' " +
                                       std::to_string(i) + " of " + std::to_string(e.count));
            }
}

}  // namespace

bool looks_like_ply(const std::filesystem::path& path) {
    // assimp picks its PLY reader by the extension (then reads whatever the
    // file holds: a .ply starting with a blank line hung it), or by "ply"
    // in any case at the start, after white space.
    std::string extension = path.extension().string();
    for (char& c : extension) c = char(std::tolower(uint8_t(c)));
    if (extension == ".ply") return true;
    std::ifstream in(path, std::ios::binary);
    char c = 0;
    while (in.get(c) && std::isspace(uint8_t(c))) {
    }
    char rest[2] = {};
    in.read(rest, 2);
    return in && std::tolower(uint8_t(c)) == 'p' && std::tolower(uint8_t(rest[0])) == 'l' &&
           std::tolower(uint8_t(rest[1])) == 'y';
}

void check_ply(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const Header h = parse_header(in, path);
    if (h.format == Format::ascii) walk_ascii(in, h, path);
    else walk_binary(in, h, path);
}

}  // namespace facet
