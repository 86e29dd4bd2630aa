// Prefiltered environments, and the split-sum table, kept on disk
// (facet/environment_map.hpp), so that a second run, or another program,
// loads one at once.
//
// Takes: a key (the images' digests and the settings that decide the
// maps), and maps to keep. Gives: the maps kept under that key, or nothing.
//
// The files are in $FACET_CACHE_DIR, else $XDG_CACHE_HOME/facet, else
// ~/.cache/facet, under environments/, each named by its key's digest; each
// holds the maps and a digest of them. FACET_CACHE_DIR=off keeps nothing. A
// file that does not read back whole and the same is named in a warning and
// made again; a folder that cannot be written is named once, and the maps
// are made each run. A file is written under another name and renamed into
// place, so that a reader never sees part of one.
#pragma once

#include "facet/environment_map.hpp"

#include <compare>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace facet {

struct EnvironmentCacheKey {
    std::vector<uint64_t> digests;  // of each file's bytes
    int size = 0, samples = 0;      // EnvironmentSettings' (size 0: the image's own)
    auto operator<=>(const EnvironmentCacheKey&) const = default;
};

// The file for `key`, or nothing when the cache is off (FACET_CACHE_DIR=off)
// or there is no folder to keep it in (no HOME).
std::optional<std::filesystem::path> environment_cache_file(const EnvironmentCacheKey& key);

// The maps kept in `file`, named `source`; nothing when there is no file,
// or (with a warning) when it is not whole. Throws Error(over_budget) when
// they would not fit the memory budget.
std::shared_ptr<const EnvironmentMaps> read_environment_cache(const std::filesystem::path& file,
                                                               const std::string& source);

// Keeps `maps` in `file`; a failure is a warning (once a process), never an
// error: the maps are in memory either way.
void write_environment_cache(const std::filesystem::path& file, const EnvironmentMaps& maps);

// The same for the split-sum table (BrdfTable's cells) of `size` x `size`
// cells of `samples` samples, made once a process: its file, the `floats`
// it holds, and keeping it.
std::optional<std::filesystem::path> brdf_cache_file(int size, int samples);
std::optional<std::vector<float>> read_brdf_cache(const std::filesystem::path& file, size_t floats);
void write_brdf_cache(const std::filesystem::path& file, const std::vector<float>& cells);

}  // namespace facet
