#include "assets/environment_cache.hpp"

#include "assets/environment_prefilter.hpp"
#include "base/file_digest.hpp"
#include "base/output_file.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <system_error>

namespace facet {

namespace {

namespace fs = std::filesystem;

// A kept file, in the host's byte order: a head (a magic, the version, four
// bytes of 0, the payload's size), the payload, and the digest of every
// byte before it. An environment's payload is a Header and its texels'
// floats; the split-sum table's, its floats. Every part is a whole number
// of 8-byte words, as BytesDigest takes them.
constexpr char kEnvironmentMagic[8] = {'f', 'a', 'c', 'e', 't', 'e', 'n', 'v'};
constexpr char kBrdfMagic[8] = {'f', 'a', 'c', 'e', 't', 'b', 'r', 'd'};
constexpr uint32_t kFormat = 1;

struct Head {
    char magic[8];
    uint32_t version, zero;
    uint64_t payload;
};
static_assert(sizeof(Head) == 24);

struct Header {
    int32_t levels;
    uint32_t size[FACET_ENVIRONMENT_MAX_LEVELS], offset[FACET_ENVIRONMENT_MAX_LEVELS];
    float irradiance[9][3];
    uint64_t floats;
};
static_assert(sizeof(Header) % 8 == 0, "the texels follow it, whole words");

uint32_t version() { return kFormat << 24 | kBrdfVersion << 16 | kPrefilterVersion; }

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
// power of two up to 2048, each level's six bordered faces after the last.
bool consistent(const Header& h) {
    if (h.levels < 1 || h.levels > FACET_ENVIRONMENT_MAX_LEVELS) return false;
    if (!std::has_single_bit(h.size[0]) || h.size[0] > 2048) return false;
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

// A kept file being read: its head and `prefix` bytes of its payload
// checked before anything large is made, then the rest.
class Reader {
public:
    Reader(const fs::path& file, const char (&magic)[8], std::string instead)
        : file_(file), instead_(std::move(instead)), in_(file, std::ios::binary) {
        std::error_code ec;
        length_ = fs::file_size(file, ec);
        exists_ = !ec && in_;
        if (exists_) check_head(magic);
    }
    bool ok() const { return ok_; }

    // Refuses the file (a warning naming it); false.
    bool refuse(const std::string& why) {
        if (ok_) spdlog::warn("{}: {}; {}", file_.string(), why, instead_);
        ok_ = false;
        return false;
    }
    // The next n bytes into `to`, into the digest.
    bool read(void* to, size_t n) {
        if (!ok_) return false;
        if (!in_.read(static_cast<char*>(to), std::streamsize(n))) return refuse("cannot be read");
        digest_.add(to, n);
        return true;
    }
    uint64_t payload() const { return head_.payload; }
    // After the payload: whether the digest matches.
    bool finish() {
        uint64_t digest;
        if (!ok_ || !in_.read(reinterpret_cast<char*>(&digest), sizeof digest))
            return refuse("cut short");
        return digest == digest_.value() || refuse("its digest does not match its contents");
    }

private:
    void check_head(const char (&magic)[8]) {
        ok_ = true;
        if (length_ < sizeof head_ + sizeof(uint64_t)) return void(refuse("cut short"));
        if (!read(&head_, sizeof head_)) return;
        if (std::memcmp(head_.magic, magic, sizeof magic) != 0)
            return void(refuse("not a file facet kept"));
        if (head_.version != version()) return void(refuse("kept by another version of facet"));
        const uint64_t room = length_ - sizeof head_ - sizeof(uint64_t);
        if (head_.payload != room)
            refuse(head_.payload > room ? "cut short" : "longer than it says");
    }

    fs::path file_;
    std::string instead_;
    std::ifstream in_;
    uintmax_t length_ = 0;
    bool exists_ = false, ok_ = false;
    Head head_{};
    BytesDigest digest_;
};

// Keeps `parts` in `file` under `magic` (OutputFile: under another name,
// renamed into place). A failure is a warning (once), never an error.
void write_kept(const fs::path& file, const char (&magic)[8],
                std::initializer_list<std::pair<const void*, size_t>> parts) {
    const fs::path folder = file.parent_path();
    try {
        std::error_code ec;
        fs::create_directories(folder, ec);
        if (ec) return warn_once_unwritable(folder, ec.message());
        Head head{};
        std::memcpy(head.magic, magic, sizeof magic);
        head.version = version();
        for (const auto& [data, n] : parts) head.payload += n;
        BytesDigest digest;
        OutputFile out(file);
        const auto put = [&](const void* data, size_t n) {
            digest.add(data, n);
            out.write(data, n);
        };
        put(&head, sizeof head);
        for (const auto& [data, n] : parts) put(data, n);
        const uint64_t value = digest.value();
        out.write(&value, sizeof value);
        out.commit();
        spdlog::debug("kept {}", file.string());
    } catch (const std::exception& e) {
        warn_once_unwritable(folder, e.what());
    }
}

bool finite(const float* v, size_t n, bool non_negative) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i]) || (non_negative && v[i] < 0.0f)) return false;
    return true;
}

}  // namespace

std::optional<fs::path> environment_cache_file(const EnvironmentCacheKey& key) {
    const std::optional<fs::path> folder = cache_folder();
    if (!folder) return std::nullopt;
    BytesDigest d;
    const uint32_t head[4] = {version(), uint32_t(key.size), uint32_t(key.samples), 0};
    d.add(head, sizeof head);
    for (const uint64_t digest : key.digests) d.add(&digest, sizeof digest);
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.env", static_cast<unsigned long long>(d.value()));
    return *folder / name;
}

std::shared_ptr<const EnvironmentMaps> read_environment_cache(const fs::path& file,
                                                               const std::string& source) {
    Reader in(file, kEnvironmentMagic, "prefiltering " + source + " again");
    Header h{};
    if (!in.ok() || !in.read(&h, sizeof h)) return nullptr;
    if (!consistent(h) || in.payload() != sizeof h + h.floats * sizeof(float))
        return in.refuse("its levels do not add up"), nullptr;
    if (h.floats * sizeof(float) > memory_budget())
        return in.refuse("over the memory budget"), nullptr;
    auto maps = std::make_shared<EnvironmentMaps>();
    maps->texels.resize(size_t(h.floats));
    if (!in.read(maps->texels.data(), maps->texels.size() * sizeof(float)) || !in.finish())
        return nullptr;
    if (!finite(maps->texels.data(), maps->texels.size(), true) ||
        !finite(&h.irradiance[0][0], 27, false))
        return in.refuse("it holds numbers no prefilter makes"), nullptr;
    maps->source = source;
    maps->levels = h.levels;
    std::memcpy(maps->size.data(), h.size, sizeof h.size);
    std::memcpy(maps->offset.data(), h.offset, sizeof h.offset);
    for (int k = 0; k < 9; ++k)
        maps->irradiance[size_t(k)] = {h.irradiance[k][0], h.irradiance[k][1], h.irradiance[k][2]};
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
    write_kept(file, kEnvironmentMagic,
               {{&h, sizeof h}, {maps.texels.data(), maps.texels.size() * sizeof(float)}});
}

std::optional<fs::path> brdf_cache_file(int size, int samples) {
    const std::optional<fs::path> folder = cache_folder();
    if (!folder) return std::nullopt;
    return *folder / ("split-sum-" + std::to_string(size) + "-" + std::to_string(samples) + "-v" +
                      std::to_string(kFormat) + "." + std::to_string(kBrdfVersion) + ".table");
}

std::optional<std::vector<float>> read_brdf_cache(const fs::path& file, size_t floats) {
    Reader in(file, kBrdfMagic, "making the table again");
    if (!in.ok()) return std::nullopt;
    if (in.payload() != floats * sizeof(float))
        return in.refuse("not a table of " + std::to_string(floats) + " numbers"), std::nullopt;
    std::vector<float> cells(floats);
    if (!in.read(cells.data(), floats * sizeof(float)) || !in.finish()) return std::nullopt;
    if (!finite(cells.data(), cells.size(), true))
        return in.refuse("it holds numbers no table has"), std::nullopt;
    return cells;
}

void write_brdf_cache(const fs::path& file, const std::vector<float>& cells) {
    write_kept(file, kBrdfMagic, {{cells.data(), cells.size() * sizeof(float)}});
}

}  // namespace facet
