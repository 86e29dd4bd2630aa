// facet screen-pass authoring layer (C++20, header-only).
//
// A screen pass (shader_abi.h, "Screen passes") works on the
// finished image of a frame: linear RGBA floats, unbounded (HDR), which it
// changes in place. The scene chains passes (`post: [...]`); each runs after
// the one before, on the host's threads. Write a pass as a struct with its
// parameters (FACET_PARAMS, <facet/declare.hpp>) and run();
// FACET_POST(YourPass) makes the plugin's descriptor:
//
//     struct Exposure {
//         static constexpr const char* name = "exposure";
//         static constexpr const char* version = "1.0";
//         FACET_PARAMS((float1, stops, 0.0f, -20.0f, 20.0f, "the image times 2^stops"))
//
//         static void run(const facet::sdk::PostFrame& f, const Params& p) {
//             const float scale = std::exp2(p.stops);
//             f.for_rows([&](int y) {
//                 glm::vec4* row = f.row(y);
//                 for (int x = 0; x < f.width(); ++x) row[x] *= glm::vec4(glm::vec3(scale), 1);
//             });
//         }
//     };
//     FACET_POST(Exposure)
//
// A pass that needs the image as it was while it writes (a blur) keeps
// copies in scratch(): memory the host keeps for the pass between frames.
// A parameter whose YAML name is no C++ identifier goes in a `params` table
// of facet_param_desc beside `struct Params` instead (see tonemap.cpp).
//
// Rules: run() is called on one thread; the functions given to
// parallel_for() and for_rows() run on several at once, and must only
// write what their index owns. Passes keep no state between frames.
#pragma once

#include <facet/boundary.hpp>
#include <facet/declare.hpp>
#include <facet/params.hpp>
#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <type_traits>

namespace facet::sdk {

// The frame a screen pass works on, and the host's services for it.
class PostFrame {
public:
    explicit PostFrame(const facet_pass_frame* frame)
        : f_(frame),
          service_(static_cast<const facet_pass_service*>(
              frame->host->extension(FACET_PASS_EXTENSION, FACET_PASS_VERSION))) {}

    int width() const { return int(f_->width); }
    int height() const { return int(f_->height); }
    int stride() const { return int(f_->stride); }  // pixels from one row to the next
    int threads() const { return int(f_->threads); }
    float time() const { return f_->time; }
    // Row y of the image (width() pixels of linear RGBA), to read and write.
    glm::vec4* row(int y) const {
        return reinterpret_cast<glm::vec4*>(f_->color) + size_t(y) * f_->stride;
    }
    // Row y of the scene's window depth; 1 - depth if reversed_z().
    const float* depth_row(int y) const { return f_->depth + size_t(y) * f_->stride; }
    bool reversed_z() const { return f_->reversed_z != 0; }
    const facet_pass_frame& abi() const { return *f_; }

    // fn(i, worker) for i in 0..count-1, on the host's threads; returns when
    // all are done. worker < threads() names the calling thread. (On a host
    // without the "facet.pass" service, one after the other, as worker 0.)
    template <class Fn>
    void parallel_for(int count, Fn&& fn) const {
        if (count <= 0) return;
        if (!service_) {
            for (int i = 0; i < count; ++i) fn(i, 0);
            return;
        }
        using F = std::remove_reference_t<Fn>;
        service_->parallel_for(
            f_, uint32_t(count),
            [](void* context, uint32_t i, uint32_t worker) {
                (*static_cast<F*>(context))(int(i), int(worker));
            },
            const_cast<void*>(static_cast<const void*>(&fn)));
    }

    // fn(y) for every row y of 0..rows-1 (by default the image's), in bands
    // of a few rows shared out to the host's threads.
    template <class Fn>
    void for_rows(Fn&& fn) const {
        for_rows(height(), fn);
    }
    template <class Fn>
    void for_rows(int rows, Fn&& fn) const {
        constexpr int kBand = 8;
        parallel_for((rows + kBand - 1) / kBand, [&](int band, int) {
            const int end = std::min(rows, (band + 1) * kBand);
            for (int y = band * kBand; y < end; ++y) fn(y);
        });
    }

    // Room for `count` values of T under `slot` (0..FACET_PASS_SCRATCH_SLOTS-1),
    // kept for this pass between frames, its contents undefined at each
    // frame's start; nullptr when the host's memory budget refuses it.
    template <class T>
    T* scratch(int slot, size_t count) const {
        static_assert(std::is_trivially_copyable_v<T> && alignof(T) <= 64);
        if (!service_) return nullptr;
        return static_cast<T*>(service_->scratch(f_, uint32_t(slot), count * sizeof(T)));
    }

private:
    const facet_pass_frame* f_;
    const facet_pass_service* service_;
};

namespace detail {

template <class P>
void post_entry(const facet_pass_frame* frame) {
    guarded(P::name, "post", [&] {
        P::run(PostFrame(frame), *static_cast<const typename P::Params*>(frame->params));
    });
}

// P's schema: from FACET_PARAMS, or from a `params` table of
// facet_param_desc (and `param_choices`), for a parameter whose name is no
// C++ identifier (tonemap's "operator").
template <class P>
facet_schema pass_schema() {
    const uint32_t size = std::is_empty_v<typename P::Params> ? 0u : uint32_t(sizeof(typename P::Params));
    if constexpr (requires { P::params.count; })
        return {P::params.count, size, P::params.count ? P::params.at.data() : nullptr,
                P::params.has_choices ? P::params.choices.data() : nullptr};
    else
        return {uint32_t(std::size(P::params)), size, std::data(P::params), choice_table<P>()};
}

}  // namespace detail

template <class P>
const facet_plugin_desc* describe_post() {
    static_assert(std::is_standard_layout_v<typename P::Params> &&
                  sizeof(typename P::Params) <= FACET_MAX_PARAMS_SIZE);
    static const facet_pass_desc pass = {static_cast<uint32_t>(sizeof(facet_pass_desc)),
                                         &detail::post_entry<P>};
    static const facet_plugin_desc desc = {
        FACET_ABI_MAJOR, FACET_ABI_MINOR, static_cast<uint32_t>(sizeof(facet_plugin_desc)),
        P::name, P::version, detail::pass_schema<P>(), nullptr, &pass,
    };
    return &desc;
}

}  // namespace facet::sdk

// Export screen pass P as this plugin's entry point. One per plugin.
#define FACET_POST(P)                                                          \
    extern "C" FACET_EXPORT const facet_plugin_desc* facet_plugin_entry(void) { \
        return ::facet::sdk::describe_post<P>();                               \
    }
