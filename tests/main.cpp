// The test programs' main: Catch2's, except that a program started with
// FACET_ISA naming a path this CPU lacks runs nothing and exits 77, which
// CTest reports as skipped (tests/CMakeLists.txt runs the raster, pipeline
// and shader tests once per path). With FACET_TEST_SKIP_BEST set too, the
// CPU's best path is skipped the same way: the main run drew on it.
// FACET_CACHE_DIR is off unless set (no prefiltered environment is kept).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <facet/error.hpp>
#include <facet/isa.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    // Prefiltered environments are not kept between runs unless a test
    // says where (test_environment.cpp): each test starts from the files.
    setenv("FACET_CACHE_DIR", "off", 1);
    try {
        const facet::Isa isa = facet::default_isa();
        if (std::getenv("FACET_TEST_SKIP_BEST") && isa == facet::best_isa()) {
            std::fprintf(stderr, "the %s path is this CPU's best, which the main run covers: "
                                 "skipped\n", std::string(facet::isa_name(isa)).c_str());
            return 77;
        }
    } catch (const facet::Error& e) {
        const bool unavailable = e.code() == facet::ErrorCode::isa_unavailable;
        std::fprintf(stderr, "%s%s\n", e.what(), unavailable ? ": skipped" : "");
        return unavailable ? 77 : 2;
    }
    return Catch::Session().run(argc, argv);
}
