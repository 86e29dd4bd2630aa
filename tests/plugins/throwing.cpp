// A shader (a screen pass with -DTHROWING_POST) whose code throws a C++
// exception from the function FACET_TEST_THROW names ("vertex",
// "fragment" or "post"), for the test of the SDK's boundary
// (test_reliability.cpp, plugins/include/facet/boundary.hpp), and never
// returns from the one FACET_TEST_STALL names, for the watchdog's.
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifdef THROWING_POST
#include <facet/post.hpp>
#else
#include <facet/shader.hpp>
#endif

namespace {

bool named(const char* variable, const char* function) {
    const char* which = std::getenv(variable);
    return which && std::strcmp(which, function) == 0;
}

void throw_in(const char* function) {
    if (named("FACET_TEST_THROW", function))
        throw std::runtime_error(std::string("thrown in ") + function + " on purpose");
    if (named("FACET_TEST_STALL", function))
        for (volatile int spin = 1; spin;) {
        }
}

#ifdef THROWING_POST
struct ThrowingPost {
    static constexpr const char* name = "throwing_post";
    static constexpr const char* version = "1.0";
    FACET_PARAMS((float1, unused, 0.0f, 0.0f, 1.0f, "nothing"))

    static void run(const facet::sdk::PostFrame&, const Params&) { throw_in("post"); }
};
#else
using namespace facet::sdk;

struct Throwing {
    static constexpr const char* name = "throwing";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs = 0;

    FACET_VARYINGS((Vec4, color))
    FACET_PARAMS((float1, unused, 0.0f, 0.0f, 1.0f, "nothing"))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        throw_in("vertex");
        clip = d.model_view_projection() * Vec4(in.position, 1.0f);
        return {in.color};
    }

    static Vec4 fragment(const Varyings& v, Fragment&, const Draw&, const Params&) {
        throw_in("fragment");
        return v.color;
    }
};
#endif

}  // namespace

#ifdef THROWING_POST
FACET_POST(ThrowingPost)
#else
FACET_SHADER(Throwing)
#endif
