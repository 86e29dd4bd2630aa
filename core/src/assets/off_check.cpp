#include "assets/off_check.hpp"

#include "facet/error.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <string>

namespace facet {

namespace {

// The first whitespace-separated word of `in`, past '#' comments; empty at
// the end of the file or past `limit` bytes of header.
std::string next_word(std::istream& in, size_t& read, size_t limit) {
    std::string word;
    for (int c; read < limit && (c = in.get()) != EOF; ++read) {
        if (c == '#' && word.empty()) {
            while (read < limit && (c = in.get()) != EOF && c != '\n') ++read;
            continue;
        }
        if (std::isspace(c)) {
            if (!word.empty()) return word;
            continue;
        }
        word.push_back(char(c));
    }
    return word;
}

std::string off_lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool is_off_keyword(const std::string& word) {
    const std::string w = off_lower(word);
    // OFF with any of its prefixes: ST, C, N, 4, n (STCN4nOFF is the longest).
    return w.size() >= 3 && w.size() <= 12 && w.compare(w.size() - 3, 3, "off") == 0;
}

[[noreturn]] void off_fail(const std::filesystem::path& path, const std::string& why) {
    throw Error(ErrorCode::mesh_load_failed, "OFF header: " + why, path.string());
}

}  // namespace

bool looks_like_off(const std::filesystem::path& path) {
    if (off_lower(path.extension().string()) == ".off") return true;
    std::ifstream in(path, std::ios::binary);
    size_t read = 0;
    return is_off_keyword(next_word(in, read, 256));
}

void check_off(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    constexpr size_t kHeader = 4096;
    size_t read = 0;
    std::string word = next_word(in, read, kHeader);
    if (is_off_keyword(word)) {
        // "nOFF" (lower-case n; NOFF is normals) puts a dimension first.
        const bool dimension = word.find("nOFF") != std::string::npos;
        word = next_word(in, read, kHeader);
        if (off_lower(word) == "binary") off_fail(path, "binary OFF is not supported");
        if (dimension) word = next_word(in, read, kHeader);
    } else if (off_lower(path.extension().string()) != ".off") {
        return;  // not OFF after all: assimp decides
    }
    // A .off file may start with its counts, without the keyword.
    unsigned long long counts[2] = {};
    for (int i = 0; i < 2; ++i) {
        if (i > 0) word = next_word(in, read, kHeader);
        char* end = nullptr;
        counts[i] = std::strtoull(word.c_str(), &end, 10);
        if (word.empty() || *end != '\0' || word[0] == '-' || counts[i] > 0xFFFFFFFFull)
            off_fail(path, "expected a vertex and a face count, got '" + word + "'");
    }
    // The fewest bytes a vertex ("0 0 0" and a separator) and a face ("1 0"
    // and a separator) take in the text.
    std::error_code ec;
    const unsigned long long size = std::filesystem::file_size(path, ec);
    const unsigned long long needed = counts[0] * 6 + counts[1] * 4;
    if (ec || needed > size)
        off_fail(path, "it declares " + std::to_string(counts[0]) + " vertices and " +
                       std::to_string(counts[1]) + " faces, more than its " +
                       std::to_string(size) + " bytes can hold");
}

}  // namespace facet
