// The memory budget: the most that facet allocates for one thing a user
// asks for (a render target, a texture, a mesh), checked before it is
// allocated, so that a size typed by mistake is an error that names it
// rather than a machine brought down by the out-of-memory killer.
//
// The budget is half of physical memory unless FACET_MAX_MEMORY says
// otherwise (parse_memory_size: "8G", "8GB", "8GiB"), or a program sets it
// (facet-render and facet-view: --max-memory). The programs refuse a
// FACET_MAX_MEMORY that is not a size (apply_max_memory); a library user
// gets a warning on standard error, and the default.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace facet {

uint64_t memory_budget();
void set_memory_budget(uint64_t bytes);

// Caps this process's address space (RLIMIT_AS, its soft limit) at what it
// maps now, plus the budget, plus room for what a program maps later that
// is not memory it uses: 256 MiB for libraries (plugins, drivers), and
// 80 MiB (a stack, and the malloc arena glibc reserves for a thread) for
// each of 2 x `threads` + 8 threads (two renderers' pools, and the
// threads of facet, MPI and the window system), `threads` being the most
// of the render threads asked for and the hardware threads. Any allocation
// past the cap fails, a plugin's included: std::bad_alloc in C++, NULL
// from malloc. Processes it starts inherit the cap (a build facet runs
// lifts it). Programs call it when the budget is set (--max-memory,
// FACET_MAX_MEMORY; apply_max_memory). Returns the cap; 0 in a build with
// AddressSanitizer or ThreadSanitizer, whose shadow memory a cap would
// break, where nothing is capped.
uint64_t cap_address_space(int threads);
// The cap cap_address_space() set (or facet-sandbox's own); 0 if none.
uint64_t address_space_cap();

// "8G", "8GB", "8GiB", "512M", "1000000", "1000000B": bytes. K, M, G and T
// (either case) are powers of 1024, with or without "B" or "iB" after them.
// Nothing for anything else (a zero, a sign, a fraction, a space, a number
// past 2^64).
std::optional<uint64_t> parse_memory_size(std::string_view text);

// "1.5 GiB", "12 MiB", "512 bytes".
std::string memory_text(uint64_t bytes);

// Throws Error(over_budget) when `bytes` is more than the budget: "`what`
// needs N, over the memory budget of M", at `file` when given.
void require_within_budget(uint64_t bytes, const std::string& what, const std::string& file = {});

}  // namespace facet
