// The test programs' main: Catch2's, except that a program started with
// FACET_ISA naming a path this CPU lacks runs nothing and exits 77, which
// CTest reports as skipped (tests/CMakeLists.txt runs the raster, pipeline
// and shader tests once per path).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <facet/error.hpp>
#include <facet/isa.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    try {
        facet::default_isa();
    } catch (const facet::Error& e) {
        const bool unavailable = e.code() == facet::ErrorCode::isa_unavailable;
        std::fprintf(stderr, "%s%s\n", e.what(), unavailable ? ": skipped" : "");
        return unavailable ? 77 : 2;
    }
    return Catch::Session().run(argc, argv);
}
