// libFuzzer's entry point for one fuzz target, chosen when it is built:
// fuzz/CMakeLists.txt compiles this file once per target, with
// FACET_FUZZ_TARGET naming its function in fuzz.hpp.
//
// A Failure (a broken rule) is printed and turned into an abort, which
// libFuzzer reports as a crash and saves the input for.
#include "fuzz.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstdlib>

#define FACET_FUZZ_STRING(x) #x
#define FACET_FUZZ_NAME(x) FACET_FUZZ_STRING(x)

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    spdlog::set_level(spdlog::level::off);  // the loaders log every file they read
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        facet::fuzz::FACET_FUZZ_TARGET(data, size);
    } catch (const facet::fuzz::Failure& failure) {
        std::fprintf(stderr, "\n==facet fuzz %s== %s\n", FACET_FUZZ_NAME(FACET_FUZZ_TARGET),
                     failure.what());
        std::abort();
    }
    return 0;
}
