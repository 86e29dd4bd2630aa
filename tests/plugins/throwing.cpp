// A shader (a screen pass with -DTHROWING_POST) whose code throws a C++
// exception from the function FACET_TEST_THROW names ("vertex",
// "fragment" or "post"), for the test of the SDK's boundary
// (test_reliability.cpp, plugins/include/facet/boundary.hpp).
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifdef THROWING_POST
#include <facet/post.hpp>
#else
#include <facet/shader.hpp>
#endif

namespace {

void throw_in(const char* function) {
    const char* which = std::getenv("FACET_TEST_THROW");
    if (which && std::strcmp(which, function) == 0)
        throw std::runtime_error(std::string("thrown in ") + function + " on purpose");
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
