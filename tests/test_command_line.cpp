// The apps' command-line helpers (apps/support, facet/command_line.hpp).
#include <facet/command_line.hpp>

#include <catch2/catch.hpp>

TEST_CASE("command-line sizes and cameras parse strictly", "[core][cli]") {
    CHECK(facet::parse_size("1280x720") == glm::ivec2(1280, 720));
    CHECK(facet::parse_size("64X48") == glm::ivec2(64, 48));
    CHECK(facet::parse_size("16384x1") == glm::ivec2(16384, 1));
    for (const char* bad : {"", "1280", "1280x", "0x720", "12x34y", "x720", "-5x5",
                            "4294967297x10", "10x4294967297", "40000x10", "+5x5", " 5x5", "5x 5", "1e3x5",
                            "5x5x5", "32769x1", "0000001x1"})
        CHECK_FALSE(facet::parse_size(bad));
    facet::Camera base;
    base.fov_y = 50.0f;
    const auto c = facet::parse_camera("1,2,3,0,0.5,-1", base);
    REQUIRE(c);
    CHECK(c->position == glm::vec3(1, 2, 3));
    CHECK(c->target == glm::vec3(0, 0.5f, -1));
    CHECK(c->fov_y == 50.0f);  // kept from the base
    CHECK(facet::parse_camera("1,2,3,0,0,0,30", base)->fov_y == 30.0f);
    for (const char* bad : {"1,2,3", "1,2,3,4,5,6,7,8", "1,2,3,1,2,3", "0,5,0,0,0,0",
                            "1,2,3,0,0,nan", "1,2,3,0,0,inf", "1,,3,0,0,0", "1,2,3,0,0,0,180",
                            "a,2,3,0,0,0"})
        CHECK_FALSE(facet::parse_camera(bad, base));
}
