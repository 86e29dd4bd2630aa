#include "assets/environment_cache.hpp"

#include "assets/environment_prefilter.hpp"
#include "base/file_digest.hpp"

#include "facet/memory.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <atomic>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

namespace facet {

namespace {

namespace fs = std::filesystem;

// A kept file, in the host's byte order: a magic, the version (kFormat
// and kPrefilterVersion), the payload's size and the payload, and the
// digest of every byte before it. An environment's payload is a Header and its texels' floats; the
// split-sum table's, its floats.
constexpr char kEnvironmentMagic[8] = {'f', 'a', 'c', 'e', 't', 'e', 'n', 'v'};
constexpr char kBrdfMagic[8] = {'f', 'a', 'c', 'e', 't', 'b', 'r', 'd'};
constexpr uint32_t kFormat = 1;

struct Header {
    int32_t levels;
    uint32_t size[FACET_ENVIRONMENT_MAX_LEVELS], offset[FACET_ENVIRONMENT_MAX_LEVELS];
    float irradiance[9][3];
    uint64_t floats;
};
static_assert(sizeof(Header) % sizeof(float) == 0, "the texels follow it in place");

uint32_t version() { return kFormat << 16 | kPrefilterVersion; }

std::optional<fs::path> cache_folder() {
    if (const char* dir = std::getenv("FACET_CACHE_DIR"); dir && *dir) {
        if (std::string_view(dir) == "off") return std::nullopt;
        return fs::path(dir) / "environments";
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return fs::path(xdg) / "facet" / "environments";
    if (const char* home = std::getenv("HOME"); home && *home)
        return fs::path(home) / ".cache" / "facet" / "environments";
    return std::nullopt;
}

// Whether `h` lays levels out as the prefilter does: halving sizes from a
// power of two, each level's six bordered faces after the last.
bool consistent(const Header& h) {
    if (h.levels < 1 || h.levels > FACET_ENVIRONMENT_MAX_LEVELS) return false;
    if (!std::has_single_bit(h.size[0]) || h.size[0] > 4096) return false;
    uint64_t texels = 0;
    for (int l = 0; l < h.levels; ++l) {
        if (h.size[l] != h.size[0] >> l || h.size[l] == 0 || h.offset[l] != texels) return false;
        texels += 6ull * (h.size[l] + 2) * (h.size[l] + 2);
    }
    return h.floats == texels * 4;
}

void warn_once_unwritable(const fs::path& folder, const std::string& why) {
    static std::atomic<bool> warned{false};
    if (warned.exchange(true)) return;
    spdlog::warn("cannot keep prefiltered environments in {}: {}; each run prefilters again "
                 "(FACET_CACHE_DIR names another folder, or off)",
                 folder.string(), why);
}

}  // namespace

std::optional<fs::path> environment_cache_file(const EnvironmentCacheKey& key) {
    const std::optional<fs::path> folder = cache_folder();
    if (!folder) return std::nullopt;
    std::string bytes;
    const auto put = [&](const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); };
    const uint32_t v = version();
    put(&v, sizeof v);
    put(&key.size, sizeof key.size);
    put(&key.samples, sizeof key.samples);
    for (const uint64_t d : key.digests) put(&d, sizeof d);
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.env",
                  static_cast<unsigned long long>(bytes_digest(bytes)));
    return *folder / name;
}

namespace {

// Every byte before a payload: the magic, the version, four bytes of 0 and
// the payload's size (a whole number of floats, so that a payload of floats
// can be read in place).
constexpr size_t kHead = 8 + 4 + 4 + 8;

// The file kept in `file` under `magic` and this version, as floats whose
// bytes are the file's (its payload from float kHead / 4 on, its digest
// last), or nothing (with a warning naming `file` and what happens
// `instead`, unless there is no file). One buffer: in a virtual machine,
// the first touch of a page costs more than the read.
std::optional<std::vector<float>> read_kept(const fs::path& file, const char (&magic)[8],
                                            const std::string& instead) {
    std::error_code ec;
    const uintmax_t length = fs::file_size(file, ec);
    if (ec) return std::nullopt;  // not kept yet
    const auto refuse = [&](const std::string& why) -> std::optional<std::vector<float>> {
        spdlog::warn("{}: {}; {}", file.string(), why, instead);
        return std::nullopt;
    };
    if (length < kHead + sizeof(uint64_t)) return refuse("cut short");
    require_within_budget(length, "a file of prefiltered maps", file.string());
    std::vector<float> words(size_t(length + 3) / 4);
    char* bytes = reinterpret_cast<char*>(words.data());
    std::ifstream in(file, std::ios::binary);
    if (!in.read(bytes, std::streamsize(length))) return refuse("cannot be read");
    if (std::memcmp(bytes, magic, sizeof magic) != 0) return refuse("not a file facet kept");
    uint32_t v;
    uint64_t size, digest;
    std::memcpy(&v, bytes + 8, sizeof v);
    std::memcpy(&size, bytes + 16, sizeof size);
    if (v != version()) return refuse("kept by another version of facet");
    const uint64_t room = length - kHead - sizeof digest;
    if (size != room) return refuse(size > room ? "cut short" : "longer than it says");
    std::memcpy(&digest, bytes + length - sizeof digest, sizeof digest);
    if (digest != bytes_digest(std::string_view(bytes, size_t(length) - sizeof digest)))
        return refuse("its digest does not match its contents");
    return words;
}

// Keeps `payload` in `file` under `magic`; a failure is a warning (once).
void write_kept(const fs::path& file, const char (&magic)[8], std::string_view payload) {
    const fs::path folder = file.parent_path();
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) return warn_once_unwritable(folder, ec.message());
    std::string bytes(magic, sizeof magic);
    const uint32_t v[2] = {version(), 0};
    bytes.append(reinterpret_cast<const char*>(v), sizeof v);
    const uint64_t size = payload.size();
    bytes.append(reinterpret_cast<const char*>(&size), sizeof size);
    bytes.append(payload);
    const uint64_t digest = bytes_digest(bytes);
    bytes.append(reinterpret_cast<const char*>(&digest), sizeof digest);
    // Another process may write the same file: each its own temporary.
    const fs::path part = file.string() + ".part" + std::to_string(::getpid());
    {
        std::ofstream out(part, std::ios::binary | std::ios::trunc);
        if (!out.write(bytes.data(), std::streamsize(bytes.size())) || !out.flush()) {
            out.close();
            fs::remove(part, ec);
            return warn_once_unwritable(folder, "writing " + part.filename().string() + " failed");
        }
    }
    fs::rename(part, file, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(part, ec);
        return warn_once_unwritable(folder, why);
    }
    spdlog::debug("kept {}", file.string());
}

}  // namespace

std::shared_ptr<const EnvironmentMaps> read_environment_cache(const fs::path& file,
                                                               const std::string& source) {
    const std::string instead = "prefiltering " + source + " again";
    std::optional<std::vector<float>> words = read_kept(file, kEnvironmentMagic, instead);
    if (!words) return nullptr;
    const size_t payload = words->size() * sizeof(float) - kHead - sizeof(uint64_t);
    Header h{};
    const auto refuse = [&](const char* why) -> std::shared_ptr<const EnvironmentMaps> {
        spdlog::warn("{}: {}; {}", file.string(), why, instead);
        return nullptr;
    };
    if (payload < sizeof h) return refuse("cut short");
    std::memcpy(&h, reinterpret_cast<const char*>(words->data()) + kHead, sizeof h);
    if (!consistent(h)) return refuse("its levels do not add up");
    if (payload != sizeof h + h.floats * sizeof(float)) return refuse("its levels do not add up");
    auto maps = std::make_shared<EnvironmentMaps>();
    maps->source = source;
    maps->levels = h.levels;
    std::memcpy(maps->size.data(), h.size, sizeof h.size);
    std::memcpy(maps->offset.data(), h.offset, sizeof h.offset);
    for (int k = 0; k < 9; ++k)
        maps->irradiance[size_t(k)] = {h.irradiance[k][0], h.irradiance[k][1], h.irradiance[k][2]};
    // The texels where they were read, moved to the front.
    const size_t first = (kHead + sizeof h) / sizeof(float);
    words->erase(words->begin(), words->begin() + std::ptrdiff_t(first));
    words->resize(size_t(h.floats));
    maps->texels = std::move(*words);
    return maps;
}

void write_environment_cache(const fs::path& file, const EnvironmentMaps& maps) {
    Header h{};
    h.levels = maps.levels;
    std::memcpy(h.size, maps.size.data(), sizeof h.size);
    std::memcpy(h.offset, maps.offset.data(), sizeof h.offset);
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) h.irradiance[k][c] = maps.irradiance[size_t(k)][c];
    h.floats = maps.texels.size();
    std::string payload(reinterpret_cast<const char*>(&h), sizeof h);
    payload.append(reinterpret_cast<const char*>(maps.texels.data()),
                   maps.texels.size() * sizeof(float));
    write_kept(file, kEnvironmentMagic, payload);
}

std::optional<fs::path> brdf_cache_file(int size, int samples) {
    const std::optional<fs::path> folder = cache_folder();
    if (!folder) return std::nullopt;
    return *folder / ("split-sum-" + std::to_string(size) + "-" + std::to_string(samples) + ".table");
}

std::optional<std::vector<float>> read_brdf_cache(const fs::path& file, size_t floats) {
    std::optional<std::vector<float>> words = read_kept(file, kBrdfMagic, "making the table again");
    if (!words) return std::nullopt;
    if (words->size() * sizeof(float) != kHead + floats * sizeof(float) + sizeof(uint64_t)) {
        spdlog::warn("{}: not a table of {} numbers; making the table again", file.string(), floats);
        return std::nullopt;
    }
    words->erase(words->begin(), words->begin() + kHead / sizeof(float));
    words->resize(floats);
    return words;
}

void write_brdf_cache(const fs::path& file, const std::vector<float>& cells) {
    write_kept(file, kBrdfMagic,
               std::string_view(reinterpret_cast<const char*>(cells.data()), cells.size() * sizeof(float)));
}

}  // namespace facet
