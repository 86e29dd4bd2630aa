#include "facet/memory.hpp"

#include "facet/error.hpp"
#include "base/isolated.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace facet {

namespace {

uint64_t physical_memory() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(8) << 30;
}

uint64_t default_budget() {
    if (const char* env = std::getenv("FACET_MAX_MEMORY"); env && *env) {
        if (const std::optional<uint64_t> bytes = parse_memory_size(env)) return *bytes;
        std::fprintf(stderr, "facet: FACET_MAX_MEMORY='%s' is not a size such as 8G; ignored\n",
                     env);
    }
    return physical_memory() / 2;
}

std::atomic<uint64_t>& budget() {
    static std::atomic<uint64_t> bytes{default_budget()};
    return bytes;
}

}  // namespace

uint64_t memory_budget() { return budget().load(); }
void set_memory_budget(uint64_t bytes) { budget() = bytes; }

std::optional<uint64_t> parse_memory_size(std::string_view text) {
    // The unit: "B", or K, M, G or T (either case) alone, with "B" or "iB".
    const bool binary = text.ends_with("iB");  // needs a unit before it
    if (binary) text.remove_suffix(2);
    else if (text.ends_with('B')) text.remove_suffix(1);
    int shift = 0;
    if (!text.empty()) {
        switch (text.back()) {
            case 'K': case 'k': shift = 10; break;
            case 'M': case 'm': shift = 20; break;
            case 'G': case 'g': shift = 30; break;
            case 'T': case 't': shift = 40; break;
            default: break;
        }
    }
    if (shift) text.remove_suffix(1);
    if ((binary && !shift) || text.empty() || text.size() > 19) return std::nullopt;
    uint64_t value = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        value = value * 10 + uint64_t(c - '0');
    }
    if (value == 0 || value > (~uint64_t(0) >> shift)) return std::nullopt;
    return value << shift;
}

std::string memory_text(uint64_t bytes) {
    const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    double value = double(bytes);
    int unit = 0;
    while (value >= 1024.0 && unit < 4) {
        value /= 1024.0;
        ++unit;
    }
    char text[32];
    std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", value, units[unit]);
    return text;
}

void require_within_budget(uint64_t bytes, const std::string& what, const std::string& file) {
    const uint64_t limit = memory_budget();
    if (bytes <= limit) return;
    throw Error(ErrorCode::over_budget,
                what + " needs " + memory_text(bytes) + "; the budget is " + memory_text(limit) +
                    " (--max-memory or FACET_MAX_MEMORY)",
                file);
}

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

}  // namespace

uint64_t cap_address_space(int threads) {
    if (kSanitized) return 0;
    const uint64_t most = std::max<uint64_t>(uint64_t(std::max(threads, 1)),
                                             std::max(1u, std::thread::hardware_concurrency()));
    const uint64_t room = (uint64_t(256) << 20) + (2 * most + 8) * (uint64_t(80) << 20);
    const uint64_t budget = memory_budget();
    return limit_address_space(budget > ~uint64_t(0) - room ? budget : budget + room);
}

}  // namespace facet
