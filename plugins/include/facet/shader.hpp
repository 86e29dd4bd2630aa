// facet shader authoring (C++20, header-only; GCC or Clang).
//
// A shader is a struct with a vertex and a fragment function, written once
// in the shading language of <facet/wide.hpp> (Float, Vec3, dot, normalize,
// select, ...), its varyings and its parameters each declared in one place.
// FACET_SHADER(YourShader) makes from it the plugin's C descriptor
// (<facet/shader_abi.h>) and the batch loops that call your functions on
// kLanes vertices or fragments at a time, inside the plugin, so that they
// inline. facet_add_shader() builds the source once per instruction-set
// path (4, 8 or 16 lanes); the same body is the reference the tests hold
// each path to (FACET_SDK_REFERENCE). A whole shader:
//
//     #include <facet/shader.hpp>
//     using namespace facet::sdk;
//     struct Tint {
//         static constexpr const char* name = "tint";
//         static constexpr const char* version = "1.0";
//         static constexpr uint32_t needs = FACET_NEED_NORMALS;
//         FACET_VARYINGS((Vec3, normal))
//         FACET_PARAMS((color4, color, {1, 1, 1, 1}, "linear RGBA"))
//         static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
//             clip = d.model_view_projection() * Vec4(in.position, 1.0f);
//             return {d.normal_matrix() * in.normal};
//         }
//         static Vec4 fragment(const Varyings& v, Fragment&, const Draw&, const Params& p) {
//             return p.color * (0.5f + 0.5f * normalize(v.normal).y);
//         }
//     };
//     FACET_SHADER(Tint)
//
// Varyings: FACET_VARYINGS((type, name[, interpolation]), ...) declares
// struct Varyings and the descriptor's table; a type is Float, Vec2, Vec3
// or Vec4, an interpolation perspective (the default), linear or flat.
// Parameters: FACET_PARAMS((kind, name, arguments...), ...) declares struct
// Params (what the fragment reads) and the schema YAML materials are
// checked against; the kinds are in params.hpp. A texture parameter names
// the varying that holds its UV: the host samples it there, for the lanes
// that need it, and Fragment::texture(p.name) reads it.
//
// Lights, shadows and AO: <facet/lighting.hpp>. Shaders are called from
// several threads at once and keep no mutable state. Conditional varyings
// (read only under a parameter, as a normal map's tangent):
//     static constexpr uint32_t conditional_varyings = 1;  // the last one
//     static constexpr const char* varyings_condition = "normal_texture";
// and, where another parameter needs them too (ABI 2.1), read under either:
//     static constexpr const char* varyings_condition_also = "gouraud";
// A second set of texture coordinates (glTF's TEXCOORD_1, ABI 2.1): need
// FACET_NEED_UV1, carry VertexIn::uv1 in a varying, and name it; a texture
// a material binds to set 1 (`uv_set: 1`) is then sampled there:
//     static constexpr const char* second_uv = "uv1";
#pragma once

#include <facet/boundary.hpp>
#include <facet/declare.hpp>
#include <facet/params.hpp>
#include <facet/shader_abi.h>
#include <facet/wide.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

namespace facet::sdk {

using namespace wide;

// ---- what the shader's functions see ---------------------------------------------

// kLanes vertices' inputs; an input the shader did not ask for (needs)
// holds its default.
struct VertexIn {
    Vec3 position;
    Vec3 normal;   // when not asked for: +Z
    Vec2 uv;       // when not asked for: 0
    Vec4 color;    // when not asked for: white
    Vec4 tangent;  // when not asked for, or the mesh has none: 0
    Vec2 uv1;      // the second UV set (FACET_NEED_UV1); when not asked for, or
                   // the mesh has none: 0
};

// A thin view of facet_draw: its uniforms as glm values.
struct Draw {
    const facet_draw* raw;
    glm::mat4 model() const { return glm::make_mat4(raw->model); }
    glm::mat4 view() const { return glm::make_mat4(raw->view); }
    glm::mat4 projection() const { return glm::make_mat4(raw->projection); }
    glm::mat4 view_projection() const { return glm::make_mat4(raw->view_projection); }
    glm::mat4 model_view_projection() const { return glm::make_mat4(raw->model_view_projection); }
    glm::mat3 normal_matrix() const { return glm::mat3(glm::make_mat4(raw->normal_matrix)); }
    glm::vec3 camera_position() const { return glm::make_vec3(raw->camera_position); }
    float time() const { return raw->time; }
    uint32_t light_count() const { return raw->light_count; }
    const facet_light& light(uint32_t i) const { return raw->lights[i]; }
};

namespace detail {
// kLanes of a batch's 16 lanes, from `first`: one fragment call's.
struct Lanes {
    int first;
    Float load(const float* a) const {
        Float f;
        std::memcpy(&f, a + first, sizeof f);
        return f;
    }
    void store(float* a, const Float& f) const { std::memcpy(a + first, &f, sizeof f); }
    // The batch's bits of these lanes, as the call's lanes (bit i: lane i).
    uint32_t of(uint32_t batch) const { return batch >> first & ((1u << kLanes) - 1u); }
};

// A texture parameter's slot by its offset in Params (in 4-byte words), or -1.
using TextureSlots = std::array<int8_t, FACET_MAX_PARAMS_SIZE / 4>;
}  // namespace detail

namespace detail {
// What the calls of one batch share: the host's textures service and the
// environment it lights by, each looked up at the first use, and whether
// the batch is a 4x4 block.
struct Batch {
    const facet_draw* draw;
    bool block;
    bool looked_up = false;
    bool environment_looked_up = false;
    const facet_textures_service* textures = nullptr;
    const facet_environment* lighting = nullptr;
    const facet_textures_service* service() {
        if (!looked_up) {  // version 1 from a host that has no 2
            for (uint32_t version : {FACET_TEXTURES_VERSION, 1u})
                if (!textures)
                    textures = static_cast<const facet_textures_service*>(
                        draw->host->extension(FACET_TEXTURES_EXTENSION, version));
        }
        looked_up = true;
        return textures;
    }
    // Its sample_grad, where the host's record has one.
    auto sample_grad() {
        const facet_textures_service* s = service();
        constexpr size_t end = offsetof(facet_textures_service, sample_grad) + sizeof(void*);
        return s && s->struct_size >= end ? s->sample_grad : nullptr;
    }
    const facet_environment* environment() {
        if (!environment_looked_up) {
            const auto* e = static_cast<const facet_environment_service*>(
                draw->host->extension(FACET_ENVIRONMENT_EXTENSION, FACET_ENVIRONMENT_VERSION));
            lighting = e && e->struct_size >= sizeof *e ? e->lighting(draw) : nullptr;
        }
        environment_looked_up = true;
        return lighting;
    }
};
}  // namespace detail

// Built-ins of kLanes fragments.
struct Fragment {
    Vec2 coord;         // pixel centres, window coordinates
    Float depth;        // window depth, 0..1
    bool front_facing;  // the same for every lane: one triangle
    Float ao;           // ambient visibility (1 when no AO was asked for)
    Mask discarded{};

    // The texel the host sampled for texture parameter `t` at each lane (at
    // the UV varying the schema names for it); white where the material
    // binds none, and for a texture that names no UV (a cube map).
    Vec4 texture(const Texture& t) const {
        const int slot = slot_of(t);
        if (!texels_ || slot < 0) return Vec4(splat(1.0f));
        const float* s = texels_ + slot * 4 * FACET_BLOCK_LANES;
        return {lanes_.load(s), lanes_.load(s + FACET_BLOCK_LANES),
                lanes_.load(s + 2 * FACET_BLOCK_LANES), lanes_.load(s + 3 * FACET_BLOCK_LANES)};
    }

    // Texture parameter `t` sampled at `uv` in each lane, with its filter
    // and wrap, at the level of detail uv's screen derivatives give (log2
    // of the longer axis of a 2x2 quad's footprint, in texels), plus
    // `bias`; a binding filtered `anisotropic` filters over the footprint
    // the derivatives span (each scaled by 2^bias). For a shader that asks
    // for FACET_NEED_DERIVATIVES (whose fragments come in whole quads;
    // packed ones read level 0). White where nothing is bound.
    Vec4 sample(const Texture& t, const Vec2& uv, float bias = 0.0f) const {
        const facet_texture_info i = info(t);
        const Vec2 dx = dFdx(uv), dy = dFdy(uv);
        const float w = float(i.width), h = float(i.height);
        const Float x2 = dx.x * dx.x * (w * w) + dx.y * dx.y * (h * h);
        const Float y2 = dy.x * dy.x * (w * w) + dy.y * dy.y * (h * h);
        const Float lod = from_quads(max(x2, y2)) + bias;
        if (!batch_->block || i.kind != FACET_TEXTURE_2D) return sample_lod(t, uv, lod);
        const float scale = bias == 0.0f ? 1.0f : std::exp2(bias);
        const Float grads[4] = {dx.x * scale, dx.y * scale, dy.x * scale, dy.y * scale};
        return sampled(t, &uv.x, 2, lod, grads);
    }
    // The same at a level of detail of each lane's own (0: level 0).
    Vec4 sample_lod(const Texture& t, const Vec2& uv, const Float& lod) const {
        return sampled(t, &uv.x, 2, lod);
    }
    // Cube map parameter `t` in direction `dir` (any length), at the level
    // of detail its screen derivatives give: log2 of the longer of its
    // quad's steps across the face, |d dir| / (2 max |dir component|), in
    // texels; plus `bias`.
    Vec4 sample_cube(const Texture& t, const Vec3& dir, float bias = 0.0f) const {
        const Vec3 dx = dFdx(dir), dy = dFdy(dir);
        const Float major = max(max(abs(dir.x), abs(dir.y)), abs(dir.z));
        const float half = 0.5f * float(info(t).width);
        const Float step2 = max(dot(dx, dx), dot(dy, dy)) * (half * half) / (major * major);
        return sample_cube_lod(t, dir, from_quads(step2) + bias);
    }
    Vec4 sample_cube_lod(const Texture& t, const Vec3& dir, const Float& lod) const {
        return sampled(t, &dir.x, 3, lod);
    }

    // Discards the lanes set in `m`.
    void discard(const Mask& m) { discarded |= m; }

    // Set by the batch loop.
    detail::Lanes lanes_{0};
    const float* texels_ = nullptr;
    const char* params_ = nullptr;
    const detail::TextureSlots* slots_ = nullptr;
    detail::Batch* batch_ = nullptr;

private:
    int slot_of(const Texture& t) const {
        const size_t word = size_t(reinterpret_cast<const char*>(&t) - params_) / 4;
        return word < slots_->size() ? (*slots_)[word] : -1;  // a Params member's
    }
    facet_texture_info info(const Texture& t) const {
        facet_texture_info i{};
        const int slot = slot_of(t);
        if (const facet_textures_service* s = batch_->service(); s && slot >= 0)
            s->info(batch_->draw, uint32_t(slot), &i);
        return i;
    }
    // 0.5 log2(rho2): the level of a footprint rho2 texels squared; level 0
    // in a packed batch, whose lanes are no quads, and for 0 or NaN.
    Float from_quads(const Float& rho2) const {
        if (!batch_->block) return splat(0.0f);
        return select(rho2 > 0.0f, 0.5f * log2(max(rho2, splat(1e-30f))), splat(0.0f));
    }
    // The service's sample, or with `grads` (du/dx, dv/dx, du/dy, dv/dy)
    // its sample_grad where the host has one.
    Vec4 sampled(const Texture& t, const Float* coords, int n, const Float& lod,
                 const Float* grads = nullptr) const {
        const facet_textures_service* s = batch_->service();
        const int slot = slot_of(t);
        if (!s || slot < 0) return Vec4(splat(1.0f));
        float c[3 * kLanes], l[kLanes], g[4 * kLanes], rgba[4 * kLanes];
        for (int k = 0; k < n; ++k) std::memcpy(c + k * kLanes, &coords[k], sizeof(Float));
        std::memcpy(l, &lod, sizeof l);
        const auto with_grads = grads ? batch_->sample_grad() : nullptr;
        if (with_grads) {
            for (int k = 0; k < 4; ++k) std::memcpy(g + k * kLanes, &grads[k], sizeof(Float));
            with_grads(batch_->draw, uint32_t(slot), c, l, g, kLanes, (1u << kLanes) - 1u, rgba);
        } else {
            s->sample(batch_->draw, uint32_t(slot), c, l, kLanes, (1u << kLanes) - 1u, rgba);
        }
        Vec4 r;
        std::memcpy(&r, rgba, sizeof r);
        return r;
    }
};

// Discards the lanes whose alpha is below `cutoff` (a cutout; see the
// `cutoff` parameter kind). 0 discards nothing.
inline void cut_out(Fragment& f, const Float& alpha, float cutoff) {
    if (cutoff > 0.0f) f.discard(alpha < cutoff);
}

// ---- the glue FACET_SHADER makes ---------------------------------------------------

namespace detail {

template <class S>
constexpr uint32_t varying_count() {
    return uint32_t(std::size(S::varyings)) - 1;  // less the end marker
}

template <class S>
constexpr uint32_t varying_floats() {
    uint32_t n = 0;
    for (uint32_t v = 0; v < varying_count<S>(); ++v) n += S::varyings[v].components;
    return n;
}

template <class S>
constexpr uint32_t conditional_varyings() {
    if constexpr (requires { S::conditional_varyings; }) return S::conditional_varyings;
    return 0;
}

constexpr bool same_text(const char* a, const char* b) {
    for (; *a && *a == *b; ++a, ++b) {}
    return *a == *b;
}

// The index of S's parameter `name` (a compile error in a constant when
// there is none).
template <class S>
constexpr uint32_t param_index(const char* name) {
    for (uint32_t i = 0; i < S::params.count; ++i)
        if (same_text(S::params.at[i].name, name)) return i;
    throw "a conditional varyings' condition names no parameter";
}

// The index of the parameter S::varyings_condition names.
template <class S>
constexpr uint32_t varyings_condition() {
    if constexpr (requires { S::varyings_condition; }) return param_index<S>(S::varyings_condition);
    return 0;
}

// 1 + the index of the parameter S::varyings_condition_also names (ABI
// 2.1), or 0.
template <class S>
constexpr uint32_t varyings_condition_also() {
    if constexpr (requires { S::varyings_condition_also; })
        return param_index<S>(S::varyings_condition_also) + 1;
    return 0;
}

// The floats before the conditional varyings.
template <class S>
constexpr uint32_t unconditional_floats() {
    uint32_t n = 0;
    for (uint32_t v = 0; v < varying_count<S>() - conditional_varyings<S>(); ++v)
        n += S::varyings[v].components;
    return n;
}

// Parameter `index`'s int32 (a TEXTURE or BOOL) in `params`.
template <class S>
int32_t int_param(const typename S::Params& params, uint32_t index) {
    int32_t value;
    std::memcpy(&value, reinterpret_cast<const unsigned char*>(&params) + S::params.at[index].offset,
                sizeof value);
    return value;
}

// The varying floats a draw with `params` reads: all, or those before the
// conditional varyings when their condition is 0 (the host leaves those
// uninterpolated).
template <class S>
uint32_t read_floats(const typename S::Params& params) {
    constexpr uint32_t all = varying_floats<S>();
    if constexpr (conditional_varyings<S>() == 0) {
        return all;
    } else {
        constexpr uint32_t unconditional = unconditional_floats<S>();
        constexpr uint32_t also = varyings_condition_also<S>();
        const bool read = int_param<S>(params, varyings_condition<S>()) != 0 ||
                          (also > 0 && int_param<S>(params, also - 1) != 0);
        return read ? all : unconditional;
    }
}

// Whether a host older than ABI 2.1, which does not know the second
// condition, left the conditional varyings out of a draw that reads them
// under it alone: the fragment function then gets zeros for them.
template <class S>
bool old_host_left_out(const facet_draw* draw, const typename S::Params& params) {
    constexpr uint32_t also = varyings_condition_also<S>();
    if constexpr (also == 0) {
        return false;
    } else {
        return draw->host->abi_minor < 1 && int_param<S>(params, also - 1) != 0 &&
               int_param<S>(params, varyings_condition<S>()) == 0;
    }
}

// 1 + the index of the varying S::second_uv names (ABI 2.1), or 0.
template <class S>
constexpr uint32_t second_uv() {
    if constexpr (requires { S::second_uv; }) {
        for (uint32_t v = 0; v < varying_count<S>(); ++v)
            if (same_text(S::varyings[v].name, S::second_uv)) return v + 1;
        throw "second_uv names no varying";  // a compile error in a constant
    }
    return 0;
}

// S's schema with each TEXTURE's UV varying found by its name.
template <class S>
constexpr auto resolved_params() {
    auto s = S::params;
    for (uint32_t i = 0; i < s.count; ++i) {
        if (!s.uv[i]) continue;
        uint32_t v = 0;
        while (v < varying_count<S>() && !same_text(S::varyings[v].name, s.uv[i])) ++v;
        if (v == varying_count<S>()) throw "a texture parameter names no varying as its UV";
        s.at[i].uv_varying = int32_t(v);
    }
    return s;
}

template <class S>
constexpr int texture_count() {
    int n = 0;
    for (uint32_t i = 0; i < S::params.count; ++i) n += S::params.at[i].type == FACET_PARAM_TEXTURE;
    return n;
}

// Each texture parameter's slot by its offset in Params.
template <class S>
constexpr TextureSlots texture_slots() {
    TextureSlots slots{};
    for (int8_t& s : slots) s = -1;
    int8_t n = 0;
    for (uint32_t i = 0; i < S::params.count; ++i)
        if (S::params.at[i].type == FACET_PARAM_TEXTURE && S::params.at[i].offset / 4 < slots.size())
            slots[S::params.at[i].offset / 4] = n++;
    return slots;
}

// Float k of Varyings, as a Float of it.
template <class V>
Float* floats_of(V& v) {
    return reinterpret_cast<Float*>(&v);
}

// kLanes vertices from `first` (the last repeated past `count`).
template <class S>
void vertex_lanes(const Draw& d, const typename S::Params& p, const facet_vertex_batch* b,
                  uint32_t first, uint32_t written) {
    VertexIn in;
    in.normal = Vec3(glm::vec3(0.0f, 0.0f, 1.0f));
    in.uv = Vec2(splat(0.0f));
    in.color = Vec4(splat(1.0f));
    in.tangent = Vec4(splat(0.0f));
    in.uv1 = Vec2(splat(0.0f));
    const auto read = [&](const float* a, int n, Float* out) {
        if (!a) return;
        for (int l = 0; l < kLanes; ++l) {
            const uint32_t i = std::min(first + uint32_t(l), b->count - 1);
            for (int c = 0; c < n; ++c) out[c][l] = a[size_t(i) * size_t(n) + size_t(c)];
        }
    };
    read(b->position, 3, &in.position.x);
    read(b->normal, 3, &in.normal.x);
    read(b->uv, 2, &in.uv.x);
    read(b->color, 4, &in.color.x);
    read(b->tangent, 4, &in.tangent.x);
    if (d.raw->host->abi_minor >= 1) read(b->uv1, 2, &in.uv1.x);  // a field of ABI 2.1
    Vec4 clip;
    typename S::Varyings out = S::vertex(in, d, p, clip);
    const uint32_t lanes = std::min(uint32_t(kLanes), b->count - first);
    // Conditional varyings the draw does not read are left unwritten: the
    // host neither interpolates nor hands them on (shader_abi.h).
    for (uint32_t l = 0; l < lanes; ++l) {
        const size_t i = first + l;
        for (int c = 0; c < 4; ++c) b->clip_position[4 * i + size_t(c)] = (&clip.x)[c][l];
        for (uint32_t k = 0; k < written; ++k)
            b->varyings[size_t(b->varying_floats) * i + k] = floats_of(out)[k][l];
    }
}

template <class S>
void vertex_batch(const facet_draw* draw, const facet_vertex_batch* b) {
    guarded(S::name, "vertex", [&] {
        const Draw d{draw};
        const auto& params = *static_cast<const typename S::Params*>(draw->params);
        const uint32_t written = read_floats<S>(params);
        for (uint32_t first = 0; first < b->count; first += kLanes)
            vertex_lanes<S>(d, params, b, first, written);
    });
}

// One fragment call: the lanes `lanes` of batch b, whose lane i is pixel
// (column[i], row[i]) of its 4x4 block (when b is a block).
template <class S>
[[gnu::always_inline]] inline void fragment_lanes(const Draw& d, const typename S::Params& params,
                                                  facet_fragment_batch* b, Batch& batch,
                                                  Lanes lanes, uint32_t read, const float* column,
                                                  const float* row) {
    constexpr int N = FACET_BLOCK_LANES;
    static constexpr TextureSlots kSlots = texture_slots<S>();
    if (!lanes.of(b->mask)) {
        for (int c = 0; c < 4; ++c) lanes.store(b->color + c * N, splat(0.0f));
        return;
    }
    typename S::Varyings v;  // the floats the draw does not read stay unset
    for (uint32_t k = 0; k < read; ++k) floats_of(v)[k] = lanes.load(b->varyings + k * N);
    Fragment f;
    if (b->coord)  // a packed batch
        f.coord = {lanes.load(b->coord), lanes.load(b->coord + N)};
    else
        f.coord = {lanes.load(column) + (float(b->x) + 0.5f), lanes.load(row) + (float(b->y) + 0.5f)};
    f.depth = lanes.load(b->depth);
    f.front_facing = b->front_facing != 0;
    f.ao = b->ao ? lanes.load(b->ao) : splat(1.0f);
    f.lanes_ = lanes;
    f.texels_ = b->texels;
    f.params_ = reinterpret_cast<const char*>(&params);
    f.slots_ = &kSlots;
    f.batch_ = &batch;
    const Vec4 c = S::fragment(v, f, d, params);
    for (int k = 0; k < 4; ++k) lanes.store(b->color + k * N, (&c.x)[k]);
    b->mask &= ~(bits(f.discarded) << lanes.first);
}

// Lane i of a block is pixel (i % 4, i / 4); in quad order, the lanes of
// each 2x2 quad follow one another.
constexpr int kQuadOrder[FACET_BLOCK_LANES] = {0, 1, 4, 5, 2, 3, 6, 7, 8, 9, 12, 13, 10, 11, 14, 15};
struct BlockPixels {
    float column[FACET_BLOCK_LANES], row[FACET_BLOCK_LANES];
    constexpr explicit BlockPixels(bool quads) : column{}, row{} {
        for (int i = 0; i < FACET_BLOCK_LANES; ++i) {
            const int lane = quads ? kQuadOrder[i] : i;
            column[i] = float(lane % 4), row[i] = float(lane / 4);
        }
    }
};

// Four lanes a call take a row of a block, which holds no whole 2x2 quad:
// for a shader that takes derivatives, the batch is copied into quad
// order, shaded, and its colours and mask put back.
template <class S>
void fragment_quads(const Draw& d, const typename S::Params& params, facet_fragment_batch* b,
                    uint32_t read, int textures) {
    constexpr int N = FACET_BLOCK_LANES;
    static constexpr BlockPixels kPixels(true);
    float varyings[FACET_MAX_VARYING_FLOATS * N], depth[N], ao[N], color[4 * N];
    float texels[FACET_MAX_TEXTURES * 4 * N];
    const auto reorder = [](const float* from, float* to, int rows) {
        for (int r = 0; r < rows; ++r)
            for (int i = 0; i < N; ++i) to[r * N + i] = from[r * N + kQuadOrder[i]];
    };
    facet_fragment_batch q = *b;
    q.mask = 0;
    for (int i = 0; i < N; ++i) q.mask |= (b->mask >> kQuadOrder[i] & 1u) << i;
    reorder(b->varyings, varyings, int(read));
    reorder(b->depth, depth, 1);
    if (b->ao) reorder(b->ao, ao, 1);
    if (b->texels) reorder(b->texels, texels, 4 * textures);
    q.varyings = varyings, q.depth = depth, q.ao = b->ao ? ao : nullptr;
    q.texels = b->texels ? texels : nullptr, q.color = color;
    Batch batch{d.raw, true};
    for (int first = 0; first < N; first += kLanes)
        fragment_lanes<S>(d, params, &q, batch, {first}, read, kPixels.column, kPixels.row);
    b->mask = 0;
    for (int i = 0; i < N; ++i) {
        b->mask |= (q.mask >> i & 1u) << kQuadOrder[i];
        for (int c = 0; c < 4; ++c) b->color[c * N + kQuadOrder[i]] = color[c * N + i];
    }
}

// A batch in calls of kLanes lanes, each holding whole 2x2 quads of a
// block, on varyings the host gave (`read` floats of them).
template <class S>
void fragment_loop_given(const Draw& d, const typename S::Params& params, facet_fragment_batch* b,
                         uint32_t read) {
    const bool block = !b->coord;
    if constexpr (kLanes == 4 && (S::needs & FACET_NEED_DERIVATIVES) != 0)
        if (block) return fragment_quads<S>(d, params, b, read, texture_count<S>());
    static constexpr BlockPixels kPixels(false);
    Batch batch{d.raw, block};
    for (int first = 0; first < FACET_BLOCK_LANES; first += kLanes)
        fragment_lanes<S>(d, params, b, batch, {first}, read, kPixels.column, kPixels.row);
}

template <class S>
void fragment_loop(const facet_draw* draw, facet_fragment_batch* b) {
    const Draw d{draw};
    const auto& params = *static_cast<const typename S::Params*>(draw->params);
    const uint32_t read = read_floats<S>(params);
    if (old_host_left_out<S>(draw, params)) [[unlikely]] {
        // The unconditional rows, then zeros for what the host left out.
        alignas(64) float varyings[FACET_MAX_VARYING_FLOATS * FACET_BLOCK_LANES] = {};
        std::memcpy(varyings, b->varyings,
                    unconditional_floats<S>() * FACET_BLOCK_LANES * sizeof(float));
        facet_fragment_batch zeroed = *b;
        zeroed.varyings = varyings;
        fragment_loop_given<S>(d, params, &zeroed, read);
        b->mask = zeroed.mask;  // the colour went where b's goes
        return;
    }
    fragment_loop_given<S>(d, params, b, read);
}

// The fragment entry: the loop, with what it throws caught (boundary.hpp).
template <class S>
void fragment_batch(const facet_draw* draw, facet_fragment_batch* b) {
    guarded(S::name, "fragment", [&] { fragment_loop<S>(draw, b); });
}

// The loop a per-path build (FACET_SDK_ISA_*) gives.
template <class S>
constexpr facet_fragment_fn path_loop() {
    return &fragment_batch<S>;
}

// Every loop works lane by lane, so the host may pack fragments from
// anywhere into a batch - unless the shader asks for derivatives, or says
// `static constexpr bool packable = false;` (its own code mixes lanes).
template <class S>
constexpr uint32_t flags() {
    bool packable = !(S::needs & FACET_NEED_DERIVATIVES);
    if constexpr (requires { S::packable; }) packable &= S::packable;
    return packable ? uint32_t(FACET_SHADER_PACKABLE) : 0u;
}

}  // namespace detail

}  // namespace facet::sdk

// The plugin's per-path fragment loops, defined by the builds
// facet_add_shader() adds (FACET_SHADER below). Weak and hidden: a plugin
// built without them (another build system, a reference build, or a host
// compiling a shader into itself) links anyway, and they read as null.
#if !defined(FACET_SDK_ISA_avx2) && !defined(FACET_SDK_ISA_avx512)
extern "C" {
__attribute__((weak, visibility("hidden"))) extern const facet_fragment_fn facet_sdk_fragment_avx2;
__attribute__((weak, visibility("hidden"))) extern const facet_fragment_fn facet_sdk_fragment_avx512;
}
#endif

namespace facet::sdk {

namespace detail {
// The fragment entries: this build's, and the per-path builds' that the
// plugin was linked with.
template <class S>
const std::pair<std::array<facet_fragment_entry, 3>, uint32_t>& fragment_entries() {
    static const auto entries = [] {
        std::pair<std::array<facet_fragment_entry, 3>, uint32_t> e{};
        e.first[e.second++] = {FACET_ISA_BASELINE, &fragment_batch<S>};
#if !defined(FACET_SDK_ISA_avx2) && !defined(FACET_SDK_ISA_avx512)
        if (&facet_sdk_fragment_avx2 && facet_sdk_fragment_avx2)
            e.first[e.second++] = {FACET_ISA_X86_64_V3, facet_sdk_fragment_avx2};
        if (&facet_sdk_fragment_avx512 && facet_sdk_fragment_avx512)
            e.first[e.second++] = {FACET_ISA_X86_64_V4, facet_sdk_fragment_avx512};
#endif
        return e;
    }();
    return entries;
}
}  // namespace detail

template <class S>
const facet_plugin_desc* describe() {
    using V = typename S::Varyings;
    using P = typename S::Params;
    static_assert(sizeof(V) == detail::varying_floats<S>() * sizeof(Float) ||
                      (detail::varying_floats<S>() == 0 && std::is_empty_v<V>),
                  "Varyings must hold exactly the floats the varyings table declares");
    static_assert(detail::varying_floats<S>() <= FACET_MAX_VARYING_FLOATS,
                  "too many varying floats");
    static_assert(std::is_standard_layout_v<P> && std::is_trivially_copyable_v<P>);
    constexpr uint32_t condition = detail::varyings_condition<S>();  // at compile time
    constexpr uint32_t second_uv = detail::second_uv<S>();
    constexpr uint32_t condition_also = detail::varyings_condition_also<S>();
    static constexpr auto kParams = detail::resolved_params<S>();
    static const facet_shader_desc shader = {
        static_cast<uint32_t>(sizeof(facet_shader_desc)), S::needs, detail::flags<S>(),
        detail::varying_count<S>(), detail::varying_count<S>() ? S::varyings : nullptr,
        detail::conditional_varyings<S>(), condition,
        &detail::vertex_batch<S>,
        detail::fragment_entries<S>().second, detail::fragment_entries<S>().first.data(),
        second_uv,
        condition_also,
    };
    static const facet_plugin_desc desc = {
        FACET_ABI_MAJOR, FACET_ABI_MINOR, static_cast<uint32_t>(sizeof(facet_plugin_desc)),
        S::name, S::version,
        {kParams.count, std::is_empty_v<P> ? 0u : static_cast<uint32_t>(sizeof(P)),
         kParams.count ? kParams.at.data() : nullptr,
         kParams.has_choices ? kParams.choices.data() : nullptr},
        &shader, nullptr,
    };
    return &desc;
}

}  // namespace facet::sdk

// Export shader struct S as this plugin's entry point. One per plugin. In a
// per-path build (facet_add_shader() defines FACET_SDK_ISA_avx2 or _avx512)
// it gives that path's fragment loop instead, which the entry point's
// descriptor then points at.
#if defined(FACET_SDK_ISA_avx2)
#define FACET_SHADER(S)                                          \
    extern "C" const facet_fragment_fn facet_sdk_fragment_avx2 = \
        ::facet::sdk::detail::path_loop<S>();
#elif defined(FACET_SDK_ISA_avx512)
#define FACET_SHADER(S)                                            \
    extern "C" const facet_fragment_fn facet_sdk_fragment_avx512 = \
        ::facet::sdk::detail::path_loop<S>();
#else
#define FACET_SHADER(S)                                                        \
    extern "C" FACET_EXPORT const facet_plugin_desc* facet_plugin_entry(void) { \
        return ::facet::sdk::describe<S>();                                    \
    }
#endif
