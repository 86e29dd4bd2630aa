// Instruction-set paths.
//
// facet compiles its hot loops (coverage, the fragment stage, pixel
// formats) once per instruction-set level and picks one at run time, so one
// build runs well on any x86-64 CPU. Shader plugins built with
// facet_add_shader() carry their wide fragment loops for the same levels,
// and the host calls the one that matches its path.
//
//   portable  the architecture's baseline: SSE2 on x86-64 (named "sse2"),
//             NEON on AArch64 ("neon"), plain C++ elsewhere ("portable").
//             Written with compiler vector extensions, no intrinsics needed.
//   avx2      x86-64-v3: AVX2, FMA, BMI1/2, F16C, LZCNT, MOVBE.
//   avx512    x86-64-v4: x86-64-v3 plus AVX-512 F, BW, CD, DQ and VL.
//
// By default a Renderer takes the best path the CPU has. The environment
// variable FACET_ISA (sse2, avx2 or avx512) forces one, as Mesa's
// LP_NATIVE_VECTOR_WIDTH does for llvmpipe; forcing a path the CPU lacks is
// an error, not a silent fallback. Every path draws the same image, bit for
// bit: the paths do the same IEEE operations in the same order (no path
// fuses a multiply and an add that another path rounds twice), only more of
// them at a time.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace facet {

enum class Isa { portable, avx2, avx512 };

// "sse2", "avx2", "avx512" (the portable path is "neon" on AArch64 and
// "portable" on other architectures).
std::string_view isa_name(Isa isa);
// The path of that name (also "portable" for the baseline), or nothing.
std::optional<Isa> parse_isa(std::string_view name);

// Built into this facet and available on this CPU (and its OS).
bool isa_supported(Isa isa);
// Every supported path, slowest first; the portable one is always there.
std::vector<Isa> supported_isas();
// The fastest supported path.
Isa best_isa();
// FACET_ISA when set, else best_isa(). Throws Error(config_invalid) for an
// unknown name and Error(isa_unavailable) for a path this CPU lacks.
Isa default_isa();
// The same check for a path asked for by name or by the caller.
Isa checked_isa(Isa isa);

// The CPU's model name ("AMD EPYC 9R14 96-Core Processor"), for reports.
std::string cpu_name();

}  // namespace facet
