// facet/wide.hpp, the SDK's shader vector maths, against double precision
// over tables of arguments, with the precision each function states. This
// file is built for the baseline (4 lanes); the shader tests hold wide
// shaders built for 8 and 16 lanes to their scalar code on every path, and
// the last test here holds the loads, built for each path, to indexing.
#include <facet/isa.hpp>
#include <facet/wide.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace facet::sdk::wide;

namespace {

// Relative error of each lane of `got` against `want(lane's argument)`,
// worst over `rounds` blocks of random arguments from `arg`.
template <class Arg, class Got, class Want>
double worst_relative(int rounds, Arg arg, Got got, Want want) {
    std::mt19937 rng(3);
    double worst = 0.0;
    for (int r = 0; r < rounds; ++r) {
        Float x;
        for (int i = 0; i < kLanes; ++i) x[i] = arg(rng);
        const Float y = got(x);
        for (int i = 0; i < kLanes; ++i) {
            const double w = want(double(x[i]));
            worst = std::max(worst, std::abs(double(y[i]) - w) / std::abs(w));
        }
    }
    return worst;
}

}  // namespace

TEST_CASE("wide sqrt, exp2 and log2 match double precision", "[wide]") {
    const auto positive = [](std::mt19937& rng) {
        return std::ldexp(std::uniform_real_distribution<float>(1.0f, 2.0f)(rng),
                          std::uniform_int_distribution<int>(-120, 120)(rng));
    };
    // Correctly rounded: within half an ulp.
    CHECK(worst_relative(2000 * 16 / kLanes, positive, [](Float x) { return sqrt(x); },
                         [](double x) { return std::sqrt(x); }) <= 0x1p-24);
    const auto exponent = [](std::mt19937& rng) {
        return std::uniform_real_distribution<float>(-125.0f, 127.0f)(rng);
    };
    CHECK(worst_relative(2000 * 16 / kLanes, exponent, [](Float y) { return exp2(y); },
                         [](double y) { return std::exp2(y); }) < 2e-7);
    // log2 near 1 is near 0: compare against |log2| + 1 instead.
    std::mt19937 rng(5);
    double worst_log = 0.0;
    for (int r = 0; r < 2000 * 16 / kLanes; ++r) {
        Float x;
        for (int i = 0; i < kLanes; ++i) x[i] = positive(rng);
        const Float l = log2(x);
        for (int i = 0; i < kLanes; ++i) {
            const double want = std::log2(double(x[i]));
            worst_log = std::max(worst_log, std::abs(l[i] - want) / (std::abs(want) + 1.0));
        }
    }
    CHECK(worst_log < 2e-7);
}

TEST_CASE("wide pow matches std::pow to 4e-6 wherever the result is above 1e-7", "[wide]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> base(0.0f, 1.0f), exponent(1.0f, 200.0f);
    double worst = 0.0;
    int counted = 0;
    for (int r = 0; r < 4000 * 16 / kLanes; ++r) {  // 64000 arguments
        Float x, y;
        for (int i = 0; i < kLanes; ++i) {
            x[i] = base(rng);
            y[i] = exponent(rng);
        }
        const Float p = pow(x, y);
        for (int i = 0; i < kLanes; ++i) {
            const double want = std::pow(double(x[i]), double(y[i]));
            if (want <= 1e-7) {
                CHECK(p[i] <= 2e-7f);
                continue;
            }
            worst = std::max(worst, std::abs(p[i] - want) / want);
            ++counted;
        }
    }
    CHECK(counted > 5000);
    CHECK(worst < 4e-6);
}

TEST_CASE("wide maths at the edges: zero, overflow, underflow and NaN", "[wide]") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(pow(splat(0.0f), 3.0f)[0] == 0.0f);
    CHECK(pow(splat(0.0f), 0.0f)[0] == 1.0f);
    CHECK(pow(splat(1.0f), 1000.0f)[0] == 1.0f);
    CHECK(std::isnan(pow(splat(nan), 2.0f)[0]));
    CHECK(std::isnan(exp2(splat(nan))[0]));
    CHECK(exp2(splat(127.9f))[0] == Approx(std::exp2(double(127.9f))).epsilon(1e-6));  // finite, near FLT_MAX
    CHECK(std::isinf(exp2(splat(128.5f))[0]));
    CHECK(exp2(splat(-140.0f))[0] == Approx(std::exp2(-140.0)).epsilon(1e-3));  // subnormal
    CHECK(exp2(splat(-200.0f))[0] == 0.0f);
    CHECK(exp2(splat(0.0f))[0] == 1.0f);
    // As std::max: a NaN first argument stays.
    CHECK(std::isnan(max(splat(nan), splat(0.0f))[0]));
    CHECK(max(splat(0.0f), splat(nan))[0] == 0.0f);
}

TEST_CASE("wide vectors: dot, normalize and reflect as glm's", "[wide]") {
    const glm::vec3 a(0.3f, -1.2f, 2.5f), n = glm::normalize(glm::vec3(0.2f, 1.0f, -0.4f));
    const Vec3 wa(a), wn(n);
    CHECK(dot(wa, wn)[kLanes - 1] == Approx(glm::dot(a, n)).epsilon(1e-6));
    const Vec3 u = normalize(wa);
    const glm::vec3 g = glm::normalize(a);
    CHECK(u.x[3] == Approx(g.x).epsilon(1e-6));
    CHECK(u.z[3] == Approx(g.z).epsilon(1e-6));
    const Vec3 r = reflect(wa, wn);
    const glm::vec3 gr = glm::reflect(a, n);
    CHECK(r.y[kLanes - 1] == Approx(gr.y).epsilon(1e-6));
    CHECK(select(splat(1.0f) > 0.0f, splat(2.0f), splat(3.0f))[0] == 2.0f);
}

TEST_CASE("wide floor and ceil as std::floor and std::ceil, gather as indexing", "[wide]") {
    const float big = 8388608.0f;  // 2^23: every float from here on is whole
    const float inf = std::numeric_limits<float>::infinity();
    const float values[] = {0.0f,  -0.0f, 0.5f,   -0.5f,  1.0f,     -1.0f,      2.999999f,
                            -2.999999f, 1e-30f, -1e-30f, big - 0.5f, -(big - 0.5f), big,
                            -big,  3e9f,  -3e9f,  inf,    -inf};
    for (float v : values) {
        INFO(v);
        CHECK(floor(splat(v))[0] == std::floor(v));
        CHECK(ceil(splat(v))[0] == std::ceil(v));
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(std::isnan(floor(splat(nan))[0]));
    CHECK(std::isnan(ceil(splat(nan))[0]));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> arg(-100.0f, 100.0f);
    for (int r = 0; r < 1000; ++r) {
        Float x;
        for (int i = 0; i < kLanes; ++i) x[i] = arg(rng);
        const Float f = floor(x), c = ceil(x);
        for (int i = 0; i < kLanes; ++i) {
            REQUIRE(f[i] == std::floor(x[i]));
            REQUIRE(c[i] == std::ceil(x[i]));
        }
    }

    float table[64];
    for (int i = 0; i < 64; ++i) table[i] = float(i) * 1.5f;
    Mask index, odd;
    for (int i = 0; i < kLanes; ++i) index[i] = (i * 37) % 64, odd[i] = i % 2 ? -1 : 0;
    const Float g = gather(table, index, odd, -7.0f);
    for (int i = 0; i < kLanes; ++i) CHECK(g[i] == (i % 2 ? table[(i * 37) % 64] : -7.0f));
}

// wide_paths.cpp, built for each path (tests/CMakeLists.txt).
extern "C" {
using WideLoads = int(const float*, const uint16_t*, const int32_t*, int, float*, float*,
                      uint64_t*, const float*, const float*, int, float*);
WideLoads facet_wide_loads_portable;
#if FACET_WIDE_LOADS_avx2
WideLoads facet_wide_loads_avx2;
#endif
#if FACET_WIDE_LOADS_avx512
WideLoads facet_wide_loads_avx512;
#endif
}

TEST_CASE("wide loads as plain indexing on every path: gather4, gather, gather_quads, bilinear4",
          "[wide][isa]") {
    std::mt19937 rng(11);
    std::vector<float> table(256);
    std::vector<uint16_t> texels(256);
    for (size_t i = 0; i < table.size(); ++i) {
        table[i] = float(i) * 0.75f - 40.0f;
        texels[i] = uint16_t(rng());
    }
    const int n = 64;
    std::vector<int32_t> index(n);
    for (int32_t& i : index) i = int32_t(rng() % 253);  // each and the three after it inside
    // bilinear4's fractions: 0, 1, and between, at random.
    std::vector<float> fx(n), fy(n);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        fx[size_t(i)] = i % 7 == 0 ? 0.0f : i % 11 == 0 ? 1.0f : unit(rng);
        fy[size_t(i)] = i % 5 == 0 ? 0.0f : i % 13 == 0 ? 1.0f : unit(rng);
    }
    const int row = 24;  // the last float read, 224 + 24 + 7 = 255: inside
    for (facet::Isa isa : facet::supported_isas()) {
        INFO("path " << facet::isa_name(isa));
        WideLoads* loads = nullptr;
        int lanes = 4;
        switch (isa) {
            case facet::Isa::portable: loads = facet_wide_loads_portable; break;
#if FACET_WIDE_LOADS_avx2
            case facet::Isa::avx2: loads = facet_wide_loads_avx2, lanes = 8; break;
#endif
#if FACET_WIDE_LOADS_avx512
            case facet::Isa::avx512: loads = facet_wide_loads_avx512, lanes = 16; break;
#endif
            default: FAIL("no loads built for this path");
        }
        std::vector<float> records(4 * n, std::nanf("")), gathered(n, std::nanf(""));
        std::vector<uint64_t> quads(n / 2, 0);
        std::vector<float> mixed(4 * n, std::nanf(""));
        CHECK(loads(table.data(), texels.data(), index.data(), n, records.data(), gathered.data(),
                    quads.data(), fx.data(), fy.data(), row, mixed.data()) == lanes);
        for (int i = 0; i < n; ++i) {
            INFO("lane " << i);
            for (int k = 0; k < 4; ++k)
                REQUIRE(records[size_t(k * n + i)] == table[size_t(index[i] + k)]);
            REQUIRE(gathered[size_t(i)] == (i % 2 ? -1.0f : table[size_t(index[i])]));
            if (i % 2 == 0) {
                uint64_t want = 0;
                for (int k = 0; k < 4; ++k)
                    want |= uint64_t(texels[size_t(index[i] + k)]) << (16 * k);
                REQUIRE(quads[size_t(i / 2)] == want);
            }
            // bilinear4: mix(mix(a, b, fx), mix(c, d, fx), fy), rounded as in lanes.
            const size_t top = size_t(index[size_t(i)] % 225), bottom = top + size_t(row);
            const float x = fx[size_t(i)], y = fy[size_t(i)];
            for (size_t k = 0; k < 4; ++k) {
                const float a = table[top + k], b = table[top + 4 + k];
                const float c = table[bottom + k], d = table[bottom + 4 + k];
                const float upper = a + (b - a) * x, lower = c + (d - c) * x;
                REQUIRE(mixed[k * size_t(n) + size_t(i)] == upper + (lower - upper) * y);
            }
        }
    }
}
