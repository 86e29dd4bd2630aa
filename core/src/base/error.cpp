#include "facet/error.hpp"

namespace facet {

namespace {

struct Entry {
    std::string_view name;
    std::string_view text;
};

constexpr Entry kErrors[] = {
#define FACET_ERROR_ENTRY(id, text) {#id, text},
    FACET_ERRORS(FACET_ERROR_ENTRY)
#undef FACET_ERROR_ENTRY
};

std::string format(ErrorCode code, const std::string& detail, const std::string& file, int line,
                   int column) {
    std::string out;
    if (!file.empty()) {
        out.append(file);
        if (line > 0) out.append(":").append(std::to_string(line));
        if (line > 0 && column > 0) out.append(":").append(std::to_string(column));
        out.append(": ");
    }
    out.append(error_text(code));
    if (!detail.empty()) out.append(": ").append(detail);
    return out;
}

}  // namespace

std::string_view error_text(ErrorCode code) { return kErrors[static_cast<int>(code)].text; }
std::string_view error_name(ErrorCode code) { return kErrors[static_cast<int>(code)].name; }

Error::Error(ErrorCode code, std::string detail, std::string file, int line, int column)
    : std::runtime_error(format(code, detail, file, line, column)),
      code_(code),
      detail_(std::move(detail)),
      file_(std::move(file)),
      line_(line),
      column_(column) {}

}  // namespace facet
