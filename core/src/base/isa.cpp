// Which instruction-set paths this CPU runs (facet/isa.hpp), from CPUID and
// from the register state the OS saves (XGETBV): a CPU may have AVX-512
// while its OS does not save the ZMM registers, and then it must not be used.
#include "facet/isa.hpp"

#include "facet/error.hpp"

#include <cstdlib>
#include <cstring>
#include <fstream>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#define FACET_X86 1
#endif

namespace facet {

namespace {

#if FACET_X86
struct CpuFeatures {
    bool avx2 = false;    // x86-64-v3
    bool avx512 = false;  // x86-64-v4
};

uint64_t xgetbv0() {
    uint32_t lo, hi;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    return uint64_t(hi) << 32 | lo;
}

CpuFeatures detect() {
    CpuFeatures f;
    unsigned a, b, c, d;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return f;
    const unsigned c1 = c;
    const bool osxsave = c1 >> 27 & 1;
    if (!osxsave || __get_cpuid_max(0, nullptr) < 7) return f;
    const uint64_t xcr0 = xgetbv0();
    const bool ymm_state = (xcr0 & 0x6) == 0x6;     // SSE and AVX registers saved
    const bool zmm_state = (xcr0 & 0xE6) == 0xE6;   // and opmask, ZMM_Hi256, Hi16_ZMM
    __cpuid_count(7, 0, a, b, c, d);
    const unsigned b7 = b;
    unsigned c81 = 0;
    if (__get_cpuid(0x80000001, &a, &b, &c, &d)) c81 = c;
    const auto has = [](unsigned reg, std::initializer_list<int> bits) {
        for (int bit : bits)
            if (!(reg >> bit & 1)) return false;
        return true;
    };
    // Everything -march=x86-64-v3 lets the compiler use, x86-64-v2's too.
    // Leaf 1 ECX: SSE3 0, SSSE3 9, FMA 12, CMPXCHG16B 13, SSE4.1 19, SSE4.2 20,
    // MOVBE 22, POPCNT 23, XSAVE 26, AVX 28, F16C 29. Leaf 0x80000001 ECX:
    // LAHF/SAHF 0, LZCNT 5. Leaf 7 EBX: BMI1 3, AVX2 5, BMI2 8; AVX-512 F 16,
    // DQ 17, CD 28, BW 30, VL 31.
    f.avx2 = ymm_state && has(c1, {0, 9, 12, 13, 19, 20, 22, 23, 26, 28, 29}) &&
             has(c81, {0, 5}) && has(b7, {3, 5, 8});
    f.avx512 = f.avx2 && zmm_state && has(b7, {16, 17, 28, 30, 31});
    return f;
}

const CpuFeatures& cpu() {
    static const CpuFeatures features = detect();
    return features;
}
#endif

std::string trim(std::string s) {
    const size_t first = s.find_first_not_of(" \t");
    const size_t last = s.find_last_not_of(" \t\n");
    return first == std::string::npos ? std::string() : s.substr(first, last - first + 1);
}

}  // namespace

std::string_view isa_name(Isa isa) {
    switch (isa) {
        case Isa::avx2: return "avx2";
        case Isa::avx512: return "avx512";
        case Isa::portable: break;
    }
#if defined(__x86_64__)
    return "sse2";
#elif defined(__aarch64__)
    return "neon";
#else
    return "portable";
#endif
}

std::optional<Isa> parse_isa(std::string_view name) {
    for (Isa isa : {Isa::portable, Isa::avx2, Isa::avx512})
        if (name == isa_name(isa)) return isa;
    if (name == "portable") return Isa::portable;
    return std::nullopt;
}

bool isa_supported(Isa isa) {
    switch (isa) {
        case Isa::portable: return true;
#if FACET_X86 && FACET_KERNELS_avx2
        case Isa::avx2: return cpu().avx2;
#endif
#if FACET_X86 && FACET_KERNELS_avx512
        case Isa::avx512: return cpu().avx512;
#endif
        default: return false;
    }
    return false;
}

std::vector<Isa> supported_isas() {
    std::vector<Isa> out;
    for (Isa isa : {Isa::portable, Isa::avx2, Isa::avx512})
        if (isa_supported(isa)) out.push_back(isa);
    return out;
}

Isa best_isa() { return supported_isas().back(); }

Isa checked_isa(Isa isa) {
    if (!isa_supported(isa))
        throw Error(ErrorCode::isa_unavailable,
                    std::string(isa_name(isa)) + " (this CPU and build run: " + [] {
                        std::string names;
                        for (Isa i : supported_isas())
                            names += (names.empty() ? "" : ", ") + std::string(isa_name(i));
                        return names;
                    }() + ")");
    return isa;
}

Isa default_isa() {
    const char* forced = std::getenv("FACET_ISA");
    if (!forced || !*forced) return best_isa();
    const std::optional<Isa> isa = parse_isa(forced);
    if (!isa)
        throw Error(ErrorCode::config_invalid,
                    "FACET_ISA=" + std::string(forced) + ": expected sse2, avx2 or avx512");
    return checked_isa(*isa);
}

std::string cpu_name() {
#if FACET_X86
    unsigned regs[12] = {};
    if (unsigned(__get_cpuid_max(0x80000000, nullptr)) >= 0x80000004u) {
        for (unsigned leaf = 0; leaf < 3; ++leaf)
            __get_cpuid(0x80000002 + leaf, &regs[4 * leaf], &regs[4 * leaf + 1],
                        &regs[4 * leaf + 2], &regs[4 * leaf + 3]);
        char brand[49] = {};
        std::memcpy(brand, regs, 48);
        if (const std::string name = trim(brand); !name.empty()) return name;
    }
#endif
    std::ifstream info("/proc/cpuinfo");
    for (std::string line; std::getline(info, line);)
        if (line.rfind("model name", 0) == 0 || line.rfind("Model", 0) == 0)
            if (const size_t colon = line.find(':'); colon != std::string::npos)
                return trim(line.substr(colon + 1));
    return "unknown CPU";
}

}  // namespace facet
