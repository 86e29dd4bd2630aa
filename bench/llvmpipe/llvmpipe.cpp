// LlvmpipeRenderer: facet's bench scenes through OSMesa and GLSL. See
// llvmpipe.hpp for what it matches and what it leaves out.
#include "llvmpipe.hpp"

#include <facet/color.hpp>

#include <facet/renderer.hpp>

// Declares every GL entry point, so that decltype can name their types; the
// functions themselves are looked up with OSMesaGetProcAddress.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <initializer_list>
#include <map>
#include <tuple>
#include <stdexcept>

namespace facet::bench {

namespace {

// The GL functions used here, without their "gl" prefix.
#define FACET_GL_FUNCTIONS(X)                                                                 \
    X(GetString) X(GetError) X(Enable) X(Disable) X(Viewport) X(ClearColor) X(ClearDepth)    \
    X(Clear) X(DepthFunc) X(DepthMask) X(CullFace) X(FrontFace) X(ClipControl) X(Finish)     \
    X(ReadPixels) X(PixelStorei) X(GenFramebuffers) X(BindFramebuffer)                       \
    X(DeleteFramebuffers) X(FramebufferRenderbuffer) X(CheckFramebufferStatus)               \
    X(GenRenderbuffers) X(BindRenderbuffer) X(RenderbufferStorage) X(DeleteRenderbuffers)    \
    X(GenBuffers) X(BindBuffer) X(BufferData) X(DeleteBuffers) X(GenVertexArrays)            \
    X(BindVertexArray) X(DeleteVertexArrays) X(EnableVertexAttribArray)                      \
    X(VertexAttribPointer) X(VertexAttrib4f) X(DrawElements) X(CreateShader)                 \
    X(ShaderSource) X(CompileShader) X(GetShaderiv) X(GetShaderInfoLog) X(DeleteShader)      \
    X(CreateProgram) X(AttachShader) X(BindAttribLocation) X(LinkProgram) X(GetProgramiv)    \
    X(GetProgramInfoLog) X(DeleteProgram) X(UseProgram) X(GetUniformLocation) X(Uniform1i)   \
    X(Uniform1f) X(Uniform3fv) X(Uniform4fv) X(Uniform1iv) X(Uniform1fv)                     \
    X(UniformMatrix3fv) X(UniformMatrix4fv) X(GenTextures) X(BindTexture) X(TexImage2D)       \
    X(TexParameteri) X(ActiveTexture) X(DeleteTextures) X(BlendFuncSeparate)                 \
    X(BlendEquationSeparate) X(BlendColor) X(ColorMask) X(ClearStencil) X(StencilMask)      \
    X(StencilFuncSeparate) X(StencilOpSeparate) X(StencilMaskSeparate) X(DrawArrays)          \
    X(LineWidth) X(PointSize) X(ProvokingVertex) X(RenderbufferStorageMultisample)            \
    X(BlitFramebuffer)

struct Gl {
#define FACET_GL_MEMBER(name) decltype(&::gl##name) name = nullptr;
    FACET_GL_FUNCTIONS(FACET_GL_MEMBER)
#undef FACET_GL_MEMBER

    void load() {
#define FACET_GL_LOAD(name)                                                          \
    name = reinterpret_cast<decltype(name)>(OSMesaGetProcAddress("gl" #name));      \
    if (!name) throw std::runtime_error("OSMesa has no gl" #name);
        FACET_GL_FUNCTIONS(FACET_GL_LOAD)
#undef FACET_GL_LOAD
    }
};

// Vertex attribute locations, shared by both programs.
enum Attribute : GLuint { kPosition = 0, kNormal = 1, kColor = 2, kUv = 3 };

constexpr int kMaxLights = 16;  // the light arrays of kPhongFragment

// phong.cpp's vertex() and fragment() in GLSL, term for term; the light
// loop is facet::sdk::incident_light and spot_cone (shader.hpp).
constexpr const char* kPhongVertex = R"(
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 3) in vec2 uv;
uniform mat4 model_view_projection;
uniform mat4 model;
uniform mat3 normal_matrix;
out vec3 world_position;
out vec3 world_normal;
out vec2 texture_uv;
void main() {
    gl_Position = model_view_projection * vec4(position, 1.0);
    world_position = vec3(model * vec4(position, 1.0));
    world_normal = normalize(normal_matrix * normal);
    texture_uv = uv;
}
)";

constexpr const char* kPhongFragment = R"(
const int kMaxLights = 16;
const int kDirectional = 0, kSpot = 2;
uniform vec3 camera_position;
uniform int light_count;
uniform int light_type[kMaxLights];
uniform vec3 light_position[kMaxLights];
uniform vec3 light_direction[kMaxLights];
uniform vec3 light_color[kMaxLights];
uniform float light_intensity[kMaxLights];
uniform float light_range[kMaxLights];
uniform vec3 light_attenuation[kMaxLights];
uniform float light_cos_inner[kMaxLights];
uniform float light_cos_outer[kMaxLights];
uniform vec3 ambient, diffuse, specular, emission;
uniform float shininess;
uniform bool blinn;
uniform sampler2D base_texture;
uniform float alpha_cutoff;
in vec3 world_position;
in vec3 world_normal;
in vec2 texture_uv;
out vec4 frag_color;

float spot_cone(int i, float cos_angle) {
    if (light_cos_inner[i] <= light_cos_outer[i])
        return cos_angle >= light_cos_outer[i] ? 1.0 : 0.0;
    return smoothstep(light_cos_outer[i], light_cos_inner[i], cos_angle);
}

// Light i arriving at p: unit vector towards it, and its radiance.
void incident_light(int i, vec3 p, out vec3 to_light, out vec3 radiance) {
    vec3 color = light_color[i] * light_intensity[i];
    if (light_type[i] == kDirectional) {
        to_light = -light_direction[i];
        radiance = color;
        return;
    }
    vec3 offset = light_position[i] - p;
    float d = length(offset);
    if (d <= 0.0 || (light_range[i] > 0.0 && d > light_range[i])) {
        to_light = vec3(0.0);
        radiance = vec3(0.0);
        return;
    }
    to_light = offset / d;
    vec3 a = light_attenuation[i];
    float scale = 1.0 / (a.x + a.y * d + a.z * d * d);
    if (light_type[i] == kSpot) scale *= spot_cone(i, dot(-to_light, light_direction[i]));
    radiance = color * scale;
}

float lobe(vec3 n, vec3 l, vec3 v) {
    float c = blinn ? dot(n, normalize(l + v)) : dot(reflect(-l, n), v);
    return pow(max(c, 0.0), shininess);
}

void main() {
    vec3 n = normalize(world_normal);
    vec3 to_eye = normalize(camera_position - world_position);
#if TEXTURED
    vec4 base = texture(base_texture, texture_uv);
#else
    vec4 base = vec4(1.0);
#endif
#if DISCARDS
    if (base.a < alpha_cutoff) discard;
#endif
    vec3 kd = diffuse * base.rgb;
    vec3 c = emission + ambient;
    for (int i = 0; i < light_count; ++i) {
        vec3 to_light, radiance;
        incident_light(i, world_position, to_light, radiance);
        float n_l = dot(n, to_light);
        if (n_l <= 0.0) continue;
        c += radiance * (kd * n_l + specular * lobe(n, to_light, to_eye));
    }
    frag_color = vec4(c, base.a);
}
)";

// unlit.cpp: vertex colour x base colour x base texture.
constexpr const char* kUnlitVertex = R"(
layout(location = 0) in vec3 position;
layout(location = 2) in vec4 color;
layout(location = 3) in vec2 uv;
uniform mat4 model_view_projection;
out vec4 vertex_color;
out vec2 texture_uv;
void main() {
    gl_Position = model_view_projection * vec4(position, 1.0);
    vertex_color = color;
    texture_uv = uv;
}
)";

constexpr const char* kUnlitFragment = R"(
uniform vec4 base_color;
uniform sampler2D base_texture;
uniform float alpha_cutoff;
in vec4 vertex_color;
in vec2 texture_uv;
out vec4 frag_color;
void main() {
    vec4 c = vertex_color * base_color;
#if TEXTURED
    c *= texture(base_texture, texture_uv);
#endif
#if DISCARDS
    if (c.a < alpha_cutoff) discard;
#endif
    frag_color = c;
}
)";

// One object's mesh in GL buffers.
struct MeshBuffers {
    GLuint vao = 0;
    GLuint buffers[6] = {};  // positions, normals, colours, UVs, indices, edges
    GLsizei index_count = 0;
    // Each part's edges in buffers[5] (first index, count), once a part is
    // drawn as lines: its triangles' sides, each once, as facet draws them.
    std::vector<std::pair<size_t, GLsizei>> edges;
};

// The sides of each part's triangles, each once (lower vertex first), the
// parts one after another, and where each part's lie.
std::vector<uint32_t> part_edges(const Mesh& mesh, std::vector<std::pair<size_t, GLsizei>>& where) {
    std::vector<uint32_t> out;
    for (size_t i = 0; i < mesh.part_count(); ++i) {
        const MeshPart part = mesh.part(i);
        std::vector<std::pair<uint32_t, uint32_t>> sides;
        for (uint32_t t = 0; t + 2 < part.index_count; t += 3)
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t a = mesh.indices[part.first_index + t + k];
                const uint32_t b = mesh.indices[part.first_index + t + (k + 1) % 3];
                if (a != b) sides.push_back({std::min(a, b), std::max(a, b)});
            }
        std::sort(sides.begin(), sides.end());
        sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
        where.push_back({out.size(), GLsizei(2 * sides.size())});
        for (const auto& [a, b] : sides) out.insert(out.end(), {a, b});
    }
    return out;
}

// A facet texture as GL sees it: its levels, filter and wrap. The same image
// bound with two filters or wraps is two GL textures.
using TextureKey = std::tuple<const Texture*, Filter, Wrap, int>;  // int: anisotropy

TextureKey texture_key(const TextureBinding& b) {
    return {b.texture.get(), b.filter, b.wrap, b.filter == Filter::anisotropic ? b.anisotropy : 1};
}

struct Program {
    GLuint id = 0;
    bool phong = false;
};

// `m`'s parameter `name`, checked against what the GLSL reads: one of
// `types`, and `bytes` of it inside the parameter block. Throws otherwise.
const facet_param_desc& checked_param(const Material& m, const char* name,
                                      std::initializer_list<uint32_t> types, size_t bytes) {
    const facet_param_desc* p = m.plugin ? m.plugin->find_param(name) : nullptr;
    if (!p || !m.block) throw std::runtime_error(m.shader + " has no parameter " + name);
    if (std::find(types.begin(), types.end(), p->type) == types.end())
        throw std::runtime_error("llvmpipe: " + m.shader + "'s parameter " + name +
                                 " has type " + std::to_string(p->type) +
                                 ", not the one its GLSL version reads");
    const size_t block = std::min<size_t>(m.plugin->schema().params_size, FACET_MAX_PARAMS_SIZE);
    if (size_t(p->offset) + bytes > block)
        throw std::runtime_error("llvmpipe: " + m.shader + "'s parameter " + name +
                                 " lies outside its parameter block");
    return *p;
}

// The value of `m`'s float parameter `name` (count 1: FLOAT; 3: VEC3 or
// COLOR3; 4: VEC4 or COLOR4), as its shader reads it from the block.
void read_param(const Material& m, const char* name, float* out, int count) {
    const size_t bytes = sizeof(float) * size_t(count);
    if (count != 1 && count != 3 && count != 4) throw std::logic_error("read_param: count");
    const facet_param_desc& p =
        count == 1   ? checked_param(m, name, {FACET_PARAM_FLOAT}, bytes)
        : count == 3 ? checked_param(m, name, {FACET_PARAM_VEC3, FACET_PARAM_COLOR3}, bytes)
                     : checked_param(m, name, {FACET_PARAM_VEC4, FACET_PARAM_COLOR4}, bytes);
    std::memcpy(out, m.block->bytes + p.offset, bytes);
}

// An INT, BOOL or TEXTURE parameter (TEXTURE: 1 when a texture is bound).
int32_t read_int_param(const Material& m, const char* name) {
    const facet_param_desc& p = checked_param(
        m, name, {FACET_PARAM_INT, FACET_PARAM_BOOL, FACET_PARAM_TEXTURE}, sizeof(int32_t));
    int32_t v = 0;
    std::memcpy(&v, m.block->bytes + p.offset, sizeof v);
    return v;
}

// The binding of m's base_texture, or null when none is bound. Throws for
// a texture the GLSL does not read (a normal map).
const TextureBinding* base_texture(const Material& m) {
    if (m.plugin && m.plugin->find_param("normal_texture") && read_int_param(m, "normal_texture"))
        throw std::runtime_error("llvmpipe: normal maps are not drawn");
    if (!read_int_param(m, "base_texture")) return nullptr;
    const int slot = m.plugin->texture_slot(*m.plugin->find_param("base_texture"));
    if (size_t(slot) >= m.textures.size() || !m.textures[size_t(slot)].texture) return nullptr;
    return &m.textures[size_t(slot)];
}

// facet's projection x view, then clip y negated: the image upside down in
// GL's window coordinates, so that GL's bottom row 0 is facet's top row
// (see make_framebuffer). Depth and clipping are unchanged.
glm::mat4 clip_from_world(const Scene& scene) {
    const RenderSettings& s = scene.settings;
    const glm::mat4 flip_y = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f));
    return flip_y * scene.camera.projection(float(s.width) / float(s.height), s.reversed_z) *
           scene.camera.view();
}

// GL's test for facet's depth comparison.
GLenum gl_compare(DepthCompare c) {
    switch (c) {
    case DepthCompare::never: return GL_NEVER;
    case DepthCompare::less: return GL_LESS;
    case DepthCompare::less_equal: return GL_LEQUAL;
    case DepthCompare::greater: return GL_GREATER;
    case DepthCompare::greater_equal: return GL_GEQUAL;
    case DepthCompare::equal: return GL_EQUAL;
    case DepthCompare::always: return GL_ALWAYS;
    }
    throw std::logic_error("unknown DepthCompare");
}

// What of `s` this renderer cannot draw as facet does, or "" when nothing.
std::string unmodelled(const RenderSettings& s) {
    if (s.msaa != 1 && s.msaa != 4)
        return "msaa " + std::to_string(s.msaa) + " (llvmpipe has 1 or 4 samples)";
    if (s.subpixel_bits != 8)
        return "subpixel_bits " + std::to_string(s.subpixel_bits) + " (llvmpipe snaps to 8)";
    if (s.wireframe) return "wireframe";
    return "";
}

void require_modelled(const RenderSettings& s) {
    if (const std::string what = unmodelled(s); !what.empty())
        throw std::runtime_error("llvmpipe side cannot model " + what);
}

const char* gl_error_name(GLenum e) {
    switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "an unknown GL error";
    }
}

// Owns an OSMesa context: destroyed last, after Impl's GL objects.
struct Context {
    OSMesaContext handle = nullptr;
    Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context() {
        if (handle) OSMesaDestroyContext(handle);
    }
};

}  // namespace

struct LlvmpipeRenderer::Impl {
    Context context;  // first member: destroyed after ~Impl has freed the GL objects
    Gl gl;
    bool gl_loaded = false;
    uint8_t window[16 * 16 * 4] = {};  // OSMesa's own buffer; frames go to `fbo`
    int width = 0, height = 0;
    LlvmpipeTarget target = LlvmpipeTarget::rgba32f;
    int samples = 1;  // the framebuffer's: 1 or 4
    GLuint fbo = 0, color = 0, depth = 0;
    GLuint resolved_fbo = 0, resolved = 0;  // its colour resolved, with samples
    std::map<const Mesh*, MeshBuffers> meshes;
    std::map<std::string, Program> programs;  // by shader name and defines
    // Each material's, found without building its key again in a timed frame
    // (upload() forgets them: a scene's materials are its own).
    std::map<const Material*, Program*> by_material;
    std::map<TextureKey, GLuint> textures;

    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl();

    void make_context();
    void make_current();
    void check_errors(const char* after);
    void make_framebuffer(int samples);
    void free_framebuffer();
    void upload_edges(const Mesh& mesh);
    GLuint compile(GLenum stage, const std::string& defines, const char* body);
    Program& program(const Material& m);
    void upload_mesh(const Mesh& mesh);
    void upload_texture(const TextureBinding& binding);
    void bind_texture(const Program& p, const Material& m);
    void set_uniforms(const Program& p, const Scene& scene, const glm::mat4& model, const Material& m,
                      const glm::mat4& view_projection);
    void set_lights(GLuint program, const Scene& scene);
    GLint uniform(GLuint program, const char* name) { return gl.GetUniformLocation(program, name); }
};

// Also runs when the constructor throws half-way: it frees what was made,
// and `context` then destroys the context.
LlvmpipeRenderer::Impl::~Impl() {
    if (!context.handle || !gl_loaded) return;
    if (!OSMesaMakeCurrent(context.handle, window, GL_UNSIGNED_BYTE, 16, 16)) return;
    for (auto& [key, t] : textures) gl.DeleteTextures(1, &t);
    for (auto& [mesh, b] : meshes) {
        gl.DeleteBuffers(6, b.buffers);
        gl.DeleteVertexArrays(1, &b.vao);
    }
    for (auto& [name, p] : programs) gl.DeleteProgram(p.id);
    free_framebuffer();
}

void LlvmpipeRenderer::Impl::free_framebuffer() {
    gl.DeleteFramebuffers(1, &fbo);
    gl.DeleteRenderbuffers(1, &color);
    gl.DeleteRenderbuffers(1, &depth);
    gl.DeleteFramebuffers(1, &resolved_fbo);
    gl.DeleteRenderbuffers(1, &resolved);
    fbo = color = depth = resolved_fbo = resolved = 0;
}

void LlvmpipeRenderer::Impl::make_context() {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              4,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              5,
                              0};
    context.handle = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context.handle)
        throw std::runtime_error("OSMesa cannot create an OpenGL 4.5 core context");
    make_current();
    gl.load();
    gl_loaded = true;
    const std::string name = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
    if (name.find("llvmpipe") == std::string::npos)
        throw std::runtime_error("OSMesa renders with " + name + ", not llvmpipe");
}

// This renderer's context, current on the calling thread.
void LlvmpipeRenderer::Impl::make_current() {
    if (!OSMesaMakeCurrent(context.handle, window, GL_UNSIGNED_BYTE, 16, 16))
        throw std::runtime_error("OSMesaMakeCurrent failed");
}

// Throws naming every GL error raised since the last check.
void LlvmpipeRenderer::Impl::check_errors(const char* after) {
    std::string names;
    for (int i = 0; i < 8; ++i) {  // GL_CONTEXT_LOST can repeat for ever
        const GLenum e = gl.GetError();
        if (e == GL_NO_ERROR) break;
        names += (names.empty() ? "" : ", ") + std::string(gl_error_name(e));
    }
    if (!names.empty()) throw std::runtime_error(std::string("llvmpipe: ") + names + " in " + after);
}

// Colour and float32 depth (with 8-bit stencil) renderbuffers of the
// frame's size and `n` samples (and with more than one, a colour buffer
// they resolve to), and the fixed-function state that matches facet's
// defaults.
void LlvmpipeRenderer::Impl::make_framebuffer(int n) {
    free_framebuffer();
    samples = n;
    const GLenum format = target == LlvmpipeTarget::rgba32f ? GL_RGBA32F : GL_SRGB8_ALPHA8;
    const auto storage = [&](GLuint& buffer, GLenum f, int s) {
        gl.GenRenderbuffers(1, &buffer);
        gl.BindRenderbuffer(GL_RENDERBUFFER, buffer);
        if (s > 1) gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, s, f, width, height);
        else gl.RenderbufferStorage(GL_RENDERBUFFER, f, width, height);
    };
    storage(color, format, n);
    storage(depth, GL_DEPTH32F_STENCIL8, n);
    gl.GenFramebuffers(1, &fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("llvmpipe: incomplete framebuffer");
    if (n > 1) {
        storage(resolved, format, 1);
        gl.GenFramebuffers(1, &resolved_fbo);
        gl.BindFramebuffer(GL_FRAMEBUFFER, resolved_fbo);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolved);
        if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("llvmpipe: incomplete framebuffer to resolve to");
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    }
    if (target == LlvmpipeTarget::srgb8) gl.Enable(GL_FRAMEBUFFER_SRGB);

    // Clip depth 0..w, as facet's projections make it. The image is drawn
    // upside down (clip_from_world) into GL's bottom-up rows, so that row 0
    // is the top row, as in facet. This also gives facet's fill rule: Mesa
    // gives a pixel centre on an edge to the triangle for which it is a left
    // edge or a bottom edge in GL's window coordinates (y up), and GL's
    // bottom is the image's top here. (tests.cpp checks this.)
    gl.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl.Enable(GL_DEPTH_TEST);
    gl.Viewport(0, 0, width, height);
    // A line's flat varyings come from its first end point, as in facet.
    gl.ProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
}

GLuint LlvmpipeRenderer::Impl::compile(GLenum stage, const std::string& defines,
                                       const char* body) {
    const GLuint s = gl.CreateShader(stage);
    const char* parts[] = {"#version 450 core\n", defines.c_str(), body};
    gl.ShaderSource(s, 3, parts, nullptr);
    gl.CompileShader(s);
    GLint ok = 0;
    gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
        throw std::runtime_error(std::string("llvmpipe: GLSL does not compile: ") + log);
    }
    return s;
}

// m's shader in GLSL, specialised as a GL programmer would write it for
// the material: the texture read only where a base texture is bound, and
// the discard only where the material may discard (Material::discards, as
// facet decides it). A shader that can discard loses llvmpipe's early
// depth test, as a facet draw that may discard is not packed.
Program& LlvmpipeRenderer::Impl::program(const Material& m) {
    if (auto it = by_material.find(&m); it != by_material.end()) return *it->second;
    const std::string defines = std::string("#define TEXTURED ") + (base_texture(m) ? "1" : "0") +
                                "\n#define DISCARDS " + (m.discards ? "1" : "0") + "\n";
    const std::string key = m.shader + "\n" + defines;
    if (auto it = programs.find(key); it != programs.end()) return *(by_material[&m] = &it->second);
    if (!supports(m.shader)) throw std::runtime_error("llvmpipe: no GLSL version of " + m.shader);
    const bool phong = m.shader == "phong";
    const GLuint vs = compile(GL_VERTEX_SHADER, defines, phong ? kPhongVertex : kUnlitVertex);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, defines, phong ? kPhongFragment : kUnlitFragment);
    Program p{gl.CreateProgram(), phong};
    gl.AttachShader(p.id, vs);
    gl.AttachShader(p.id, fs);
    gl.LinkProgram(p.id);
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    GLint ok = 0;
    gl.GetProgramiv(p.id, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.GetProgramInfoLog(p.id, sizeof log, nullptr, log);
        throw std::runtime_error(std::string("llvmpipe: GLSL does not link: ") + log);
    }
    Program& made = programs[key] = p;
    return *(by_material[&m] = &made);
}

// Positions, normals, colours and UVs in separate buffers, plus 32-bit
// indices. A mesh without normals, colours or UVs gets facet's defaults for
// the missing input (+Z, white, 0) as a constant attribute.
void LlvmpipeRenderer::Impl::upload_mesh(const Mesh& mesh) {
    if (meshes.count(&mesh)) return;
    MeshBuffers& b = meshes[&mesh];
    gl.GenVertexArrays(1, &b.vao);
    gl.BindVertexArray(b.vao);
    gl.GenBuffers(6, b.buffers);
    auto attribute = [&](GLuint location, GLuint buffer, const void* data, size_t count,
                         int components) {
        gl.BindBuffer(GL_ARRAY_BUFFER, buffer);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(count * components * sizeof(float)), data,
                      GL_STATIC_DRAW);
        gl.EnableVertexAttribArray(location);
        gl.VertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, 0, nullptr);
    };
    attribute(kPosition, b.buffers[0], mesh.positions.data(), mesh.positions.size(), 3);
    if (!mesh.normals.empty())
        attribute(kNormal, b.buffers[1], mesh.normals.data(), mesh.normals.size(), 3);
    else
        gl.VertexAttrib4f(kNormal, 0.0f, 0.0f, 1.0f, 1.0f);
    if (!mesh.colors.empty())
        attribute(kColor, b.buffers[2], mesh.colors.data(), mesh.colors.size(), 4);
    else
        gl.VertexAttrib4f(kColor, 1.0f, 1.0f, 1.0f, 1.0f);
    if (!mesh.uvs.empty())
        attribute(kUv, b.buffers[3], mesh.uvs.data(), mesh.uvs.size(), 2);
    else
        gl.VertexAttrib4f(kUv, 0.0f, 0.0f, 0.0f, 1.0f);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffers[4]);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)),
                  mesh.indices.data(), GL_STATIC_DRAW);
    b.index_count = GLsizei(mesh.indices.size());
    gl.BindVertexArray(0);
}

void LlvmpipeRenderer::Impl::upload_edges(const Mesh& mesh) {
    MeshBuffers& b = meshes.at(&mesh);
    if (!b.edges.empty()) return;
    const std::vector<uint32_t> edges = part_edges(mesh, b.edges);
    gl.BindBuffer(GL_ARRAY_BUFFER, b.buffers[5]);  // bound as indices when drawn
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(edges.size() * sizeof(uint32_t)), edges.data(),
                  GL_STATIC_DRAW);
}

// GL's minification filter, magnification filter and wrap for facet's.
GLint gl_min_filter(Filter f) {
    switch (f) {
    case Filter::nearest: return GL_NEAREST;
    case Filter::bilinear: return GL_LINEAR;
    case Filter::trilinear: return GL_LINEAR_MIPMAP_LINEAR;
    case Filter::anisotropic: return GL_LINEAR_MIPMAP_LINEAR;  // with its most samples
    }
    throw std::logic_error("unknown Filter");
}

GLint gl_wrap(Wrap w) {
    switch (w) {
    case Wrap::repeat: return GL_REPEAT;
    case Wrap::clamp: return GL_CLAMP_TO_EDGE;
    case Wrap::mirror: return GL_MIRRORED_REPEAT;
    }
    throw std::logic_error("unknown Wrap");
}

// The texture with facet's own mip chain (the same levels, made the same
// way), GL_SRGB8_ALPHA8 for colour and GL_RGBA8 for data: llvmpipe decodes
// sRGB before it filters, as facet does. Its rows go up in the order facet
// stores them, so that t = 0 is facet's v = 0, the top row's edge.
void LlvmpipeRenderer::Impl::upload_texture(const TextureBinding& b) {
    const TextureKey key = texture_key(b);
    if (textures.count(key)) return;
    const Texture& t = *b.texture;
    GLuint& id = textures[key];
    gl.GenTextures(1, &id);
    gl.BindTexture(GL_TEXTURE_2D, id);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const GLint format = t.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
    const int levels = mipmapped(b.filter) ? t.levels() : 1;
    for (int i = 0; i < levels; ++i) {
        const MipLevel* m = i ? &t.mips[size_t(i - 1)] : nullptr;
        gl.TexImage2D(GL_TEXTURE_2D, i, format, m ? m->width : t.width, m ? m->height : t.height,
                      0, GL_RGBA, GL_UNSIGNED_BYTE, m ? m->texels.data() : t.texels.data());
    }
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, gl_min_filter(b.filter));
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER,
                     b.filter == Filter::nearest ? GL_NEAREST : GL_LINEAR);
    if (b.filter == Filter::anisotropic)  // GL 4.6 (and EXT_texture_filter_anisotropic)
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY, b.anisotropy);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, gl_wrap(b.wrap));
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, gl_wrap(b.wrap));
}

// Material m's base texture on unit 0, or none; and its alpha cutoff.
void LlvmpipeRenderer::Impl::bind_texture(const Program& p, const Material& m) {
    const TextureBinding* b = base_texture(m);
    gl.Uniform1i(uniform(p.id, "base_texture"), 0);
    float cutoff = 0.0f;
    read_param(m, "alpha_cutoff", &cutoff, 1);
    gl.Uniform1f(uniform(p.id, "alpha_cutoff"), cutoff);
    if (!b) return;
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, textures.at(texture_key(*b)));
}

// The lights as facet hands them to a shader (to_abi), one array per field.
void LlvmpipeRenderer::Impl::set_lights(GLuint p, const Scene& scene) {
    if (scene.lights.size() > size_t(kMaxLights))
        throw std::runtime_error("llvmpipe: more than 16 lights");
    const int n = int(scene.lights.size());
    int type[kMaxLights];
    float position[kMaxLights][3], direction[kMaxLights][3], color[kMaxLights][3],
        attenuation[kMaxLights][3];
    float intensity[kMaxLights], range[kMaxLights], cos_inner[kMaxLights], cos_outer[kMaxLights];
    for (int i = 0; i < n; ++i) {
        const facet_light l = to_abi(scene.lights[size_t(i)]);
        type[i] = int(l.type);
        std::memcpy(position[i], l.position, sizeof position[i]);
        std::memcpy(direction[i], l.direction, sizeof direction[i]);
        std::memcpy(color[i], l.color, sizeof color[i]);
        std::memcpy(attenuation[i], l.attenuation, sizeof attenuation[i]);
        intensity[i] = l.intensity;
        range[i] = l.range;
        cos_inner[i] = l.spot_cos_inner;
        cos_outer[i] = l.spot_cos_outer;
    }
    gl.Uniform1i(uniform(p, "light_count"), n);
    if (n == 0) return;
    gl.Uniform1iv(uniform(p, "light_type"), n, type);
    gl.Uniform3fv(uniform(p, "light_position"), n, &position[0][0]);
    gl.Uniform3fv(uniform(p, "light_direction"), n, &direction[0][0]);
    gl.Uniform3fv(uniform(p, "light_color"), n, &color[0][0]);
    gl.Uniform3fv(uniform(p, "light_attenuation"), n, &attenuation[0][0]);
    gl.Uniform1fv(uniform(p, "light_intensity"), n, intensity);
    gl.Uniform1fv(uniform(p, "light_range"), n, range);
    gl.Uniform1fv(uniform(p, "light_cos_inner"), n, cos_inner);
    gl.Uniform1fv(uniform(p, "light_cos_outer"), n, cos_outer);
}

// The matrices facet's draw() gives a shader, and the material's values.
void LlvmpipeRenderer::Impl::set_uniforms(const Program& p, const Scene& scene,
                                          const glm::mat4& model, const Material& m,
                                          const glm::mat4& view_projection) {
    const glm::mat4 mvp = view_projection * model;
    gl.UniformMatrix4fv(uniform(p.id, "model_view_projection"), 1, GL_FALSE,
                        glm::value_ptr(mvp));
    bind_texture(p, m);
    if (!p.phong) {
        float base_color[4];
        read_param(m, "base_color", base_color, 4);
        gl.Uniform4fv(uniform(p.id, "base_color"), 1, base_color);
        return;
    }
    const glm::mat3 normals = normal_matrix(model);
    gl.UniformMatrix4fv(uniform(p.id, "model"), 1, GL_FALSE, glm::value_ptr(model));
    gl.UniformMatrix3fv(uniform(p.id, "normal_matrix"), 1, GL_FALSE, glm::value_ptr(normals));
    gl.Uniform3fv(uniform(p.id, "camera_position"), 1, glm::value_ptr(scene.camera.position));
    for (const char* name : {"ambient", "diffuse", "specular", "emission"}) {
        float rgb[3];
        read_param(m, name, rgb, 3);
        gl.Uniform3fv(uniform(p.id, name), 1, rgb);
    }
    float shininess = 0.0f;
    read_param(m, "shininess", &shininess, 1);
    gl.Uniform1f(uniform(p.id, "shininess"), shininess);
    gl.Uniform1i(uniform(p.id, "blinn"), read_int_param(m, "blinn"));
    set_lights(p.id, scene);
}

LlvmpipeRenderer::LlvmpipeRenderer(int width, int height, LlvmpipeTarget target)
    : impl_(std::make_unique<Impl>()) {
    impl_->width = width;
    impl_->height = height;
    impl_->target = target;
    impl_->make_context();
    impl_->make_framebuffer(1);
    impl_->check_errors("making the framebuffer");
}

LlvmpipeRenderer::~LlvmpipeRenderer() = default;

bool LlvmpipeRenderer::supports(const std::string& shader) {
    return shader == "phong" || shader == "unlit";
}

std::string LlvmpipeRenderer::renderer_name() const {
    auto text = [&](GLenum name) {
        return std::string(reinterpret_cast<const char*>(impl_->gl.GetString(name)));
    };
    return text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION);
}

void LlvmpipeRenderer::upload(const Scene& scene) {
    require_modelled(scene.settings);
    impl_->make_current();
    impl_->by_material.clear();
    for (const Object& o : scene.objects) {
        if (!o.visible || !o.mesh) continue;
        for (const Material* m : o.materials()) {
            if (m->alpha_to_coverage)
                throw std::runtime_error("llvmpipe: alpha_to_coverage is not drawn (GL picks "
                                         "other samples than facet's dither)");
            impl_->program(*m);
            if (const TextureBinding* b = base_texture(*m)) {
                if (!b->transform.identity() || b->uv_set != 0)
                    throw std::runtime_error("llvmpipe: a base texture with a transform or on a "
                                             "second UV set is not drawn");
                impl_->upload_texture(*b);
            }
        }
        impl_->upload_mesh(*o.mesh);
        for (size_t i = 0; i < o.mesh->part_count(); ++i)
            if (const Material* m = o.material_of(i); m && m->draw == Topology::lines)
                impl_->upload_edges(*o.mesh);
    }
    if (scene.settings.msaa != impl_->samples) impl_->make_framebuffer(scene.settings.msaa);
    impl_->check_errors("upload()");
}

namespace {

GLenum gl_factor(BlendFactor f) {
    using F = BlendFactor;
    switch (f) {
        case F::zero: return GL_ZERO;
        case F::one: return GL_ONE;
        case F::src_color: return GL_SRC_COLOR;
        case F::one_minus_src_color: return GL_ONE_MINUS_SRC_COLOR;
        case F::dst_color: return GL_DST_COLOR;
        case F::one_minus_dst_color: return GL_ONE_MINUS_DST_COLOR;
        case F::src_alpha: return GL_SRC_ALPHA;
        case F::one_minus_src_alpha: return GL_ONE_MINUS_SRC_ALPHA;
        case F::dst_alpha: return GL_DST_ALPHA;
        case F::one_minus_dst_alpha: return GL_ONE_MINUS_DST_ALPHA;
        case F::constant_color: return GL_CONSTANT_COLOR;
        case F::one_minus_constant_color: return GL_ONE_MINUS_CONSTANT_COLOR;
        case F::constant_alpha: return GL_CONSTANT_ALPHA;
        case F::one_minus_constant_alpha: return GL_ONE_MINUS_CONSTANT_ALPHA;
        case F::src_alpha_saturate: return GL_SRC_ALPHA_SATURATE;
    }
    return GL_ZERO;
}

GLenum gl_equation(BlendOp op) {
    switch (op) {
        case BlendOp::add: return GL_FUNC_ADD;
        case BlendOp::subtract: return GL_FUNC_SUBTRACT;
        case BlendOp::reverse_subtract: return GL_FUNC_REVERSE_SUBTRACT;
        case BlendOp::min: return GL_MIN;
        case BlendOp::max: return GL_MAX;
    }
    return GL_FUNC_ADD;
}

// facet's blend of `m` as GL's: the named modes as their factors (the
// same where the source alpha is within 0..1).
void set_blend(Gl& gl, const Material& m) {
    if (m.blend == BlendMode::opaque) {
        gl.Disable(GL_BLEND);
        return;
    }
    BlendFunc f = m.blend_func;
    if (m.blend != BlendMode::custom) {
        f = BlendFunc{};
        f.src_color = BlendFactor::src_alpha;
        f.dst_color = m.blend == BlendMode::alpha ? BlendFactor::one_minus_src_alpha : BlendFactor::one;
        f.src_alpha = m.blend == BlendMode::alpha ? BlendFactor::one : BlendFactor::zero;
        f.dst_alpha = m.blend == BlendMode::alpha ? BlendFactor::one_minus_src_alpha : BlendFactor::one;
    }
    gl.Enable(GL_BLEND);
    gl.BlendFuncSeparate(gl_factor(f.src_color), gl_factor(f.dst_color), gl_factor(f.src_alpha),
                         gl_factor(f.dst_alpha));
    gl.BlendEquationSeparate(gl_equation(f.color_op), gl_equation(f.alpha_op));
    gl.BlendColor(f.constant[0], f.constant[1], f.constant[2], f.constant[3]);
}

GLenum gl_stencil_compare(StencilCompare c) {
    switch (c) {
    case StencilCompare::never: return GL_NEVER;
    case StencilCompare::less: return GL_LESS;
    case StencilCompare::less_equal: return GL_LEQUAL;
    case StencilCompare::greater: return GL_GREATER;
    case StencilCompare::greater_equal: return GL_GEQUAL;
    case StencilCompare::equal: return GL_EQUAL;
    case StencilCompare::not_equal: return GL_NOTEQUAL;
    case StencilCompare::always: return GL_ALWAYS;
    }
    return GL_ALWAYS;
}

GLenum gl_stencil_op(StencilOp o) {
    switch (o) {
    case StencilOp::keep: return GL_KEEP;
    case StencilOp::zero: return GL_ZERO;
    case StencilOp::replace: return GL_REPLACE;
    case StencilOp::increment: return GL_INCR;
    case StencilOp::increment_wrap: return GL_INCR_WRAP;
    case StencilOp::decrement: return GL_DECR;
    case StencilOp::decrement_wrap: return GL_DECR_WRAP;
    case StencilOp::invert: return GL_INVERT;
    }
    return GL_KEEP;
}

// facet's colour mask and stencil state of `m` as GL's, each facing's own.
void set_stencil(Gl& gl, const Material& m) {
    const GLboolean c = m.color_write ? GL_TRUE : GL_FALSE;
    gl.ColorMask(c, c, c, c);
    if (!m.stencil.enabled) {
        gl.Disable(GL_STENCIL_TEST);
        return;
    }
    gl.Enable(GL_STENCIL_TEST);
    for (const auto& [face, f] : {std::pair{GLenum(GL_FRONT), m.stencil.front},
                                  std::pair{GLenum(GL_BACK), m.stencil.back}}) {
        gl.StencilFuncSeparate(face, gl_stencil_compare(f.compare), f.reference, f.read_mask);
        gl.StencilOpSeparate(face, gl_stencil_op(f.fail), gl_stencil_op(f.depth_fail),
                             gl_stencil_op(f.pass));
        gl.StencilMaskSeparate(face, f.write_mask);
    }
}

// Part `index` of a mesh as its material draws it: its triangles, its
// edges as lines (upload_edges) or its vertices as points, with the
// material's width or size.
void draw_part(Gl& gl, const MeshBuffers& b, const MeshPart& part, size_t index, const Material& m) {
    gl.BindVertexArray(b.vao);
    switch (m.draw) {
        case Topology::triangles:
            gl.DrawElements(GL_TRIANGLES, GLsizei(part.index_count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(uintptr_t(part.first_index) * 4));
            break;
        case Topology::lines:
            if (index >= b.edges.size())
                throw std::runtime_error("llvmpipe: a part is drawn as lines that upload() did "
                                         "not upload as lines");
            gl.LineWidth(m.line_width);
            gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffers[5]);
            gl.DrawElements(GL_LINES, b.edges.at(index).second, GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(b.edges[index].first * 4));
            gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffers[4]);  // the VAO's own again
            break;
        case Topology::points:
            gl.PointSize(m.point_size);
            gl.DrawArrays(GL_POINTS, GLint(part.first_vertex), GLsizei(part.vertex_count));
            break;
    }
}

struct DrawnPart {
    const Object* object;
    size_t part;
};

// Each visible part with a material, in facet's order (renderer.cpp's
// draw_main_pass): opaque ones in scene order, then blended ones farthest
// first by the view depth of their bounds' centre, ties in scene order.
std::vector<DrawnPart> draw_order(const Scene& scene) {
    std::vector<DrawnPart> opaque;
    std::vector<std::pair<float, DrawnPart>> blended;
    const glm::mat4 view = scene.camera.view();
    for (const Object& o : scene.objects) {
        if (!o.visible || !o.mesh) continue;
        for (size_t i = 0; i < o.mesh->part_count(); ++i) {  // as add_draw_items
            const Material* m = o.material_of(i);
            if (!m) continue;
            if (m->blend == BlendMode::opaque) {
                opaque.push_back({&o, i});
                continue;
            }
            const Bounds& b = o.mesh->part(i).bounds;
            const glm::vec3 centre = 0.5f * (b.min + b.max);
            blended.push_back({(view * o.part_matrix(i) * glm::vec4(centre, 1.0f)).z, {&o, i}});
        }
    }
    std::stable_sort(blended.begin(), blended.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [depth, d] : blended) opaque.push_back(d);
    return opaque;
}

}  // namespace

// Each draw follows facet's PipelineState for it (renderer.cpp's
// pipeline_state): cull mode, front face, depth test, depth writes,
// blending, the colour mask and the stencil.
double LlvmpipeRenderer::render(const Scene& scene) {
    Gl& gl = impl_->gl;
    const RenderSettings& s = scene.settings;
    require_modelled(s);
    impl_->make_current();
    const auto start = std::chrono::steady_clock::now();
    if (s.msaa != impl_->samples)
        throw std::runtime_error("llvmpipe: render() of msaa " + std::to_string(s.msaa) +
                                 " after upload() of msaa " + std::to_string(impl_->samples));
    gl.BindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
    gl.ClearColor(s.clear_color.r, s.clear_color.g, s.clear_color.b, s.clear_color.a);
    gl.ClearDepth(s.reversed_z ? 0.0 : 1.0);  // RenderSettings::far_depth(), as Renderer clears
    gl.DepthFunc(gl_compare(s.depth_compare));
    gl.ClearStencil(s.clear_stencil);
    gl.DepthMask(GL_TRUE);  // glClear honours the depth, colour and stencil masks
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.StencilMask(0xFF);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    // The flip in clip_from_world mirrors every triangle's winding.
    gl.FrontFace(s.front_ccw ? GL_CW : GL_CCW);
    const glm::mat4 view_projection = clip_from_world(scene);
    for (const DrawnPart& d : draw_order(scene)) {
        const Material& m = *d.object->material_of(d.part);
        const CullMode cull = m.cull.value_or(s.cull);
        if (cull == CullMode::none) gl.Disable(GL_CULL_FACE);
        else {
            gl.Enable(GL_CULL_FACE);
            gl.CullFace(cull == CullMode::back ? GL_BACK : GL_FRONT);
        }
        gl.DepthMask(m.writes_depth() ? GL_TRUE : GL_FALSE);
        set_blend(gl, m);
        set_stencil(gl, m);
        const Program& p = impl_->program(m);
        gl.UseProgram(p.id);
        impl_->set_uniforms(p, scene, d.object->part_matrix(d.part), m, view_projection);
        draw_part(gl, impl_->meshes.at(d.object->mesh.get()), d.object->mesh->part(d.part), d.part, m);
    }
    gl.Finish();
    const auto end = std::chrono::steady_clock::now();
    impl_->check_errors("render()");
    return std::chrono::duration<double, std::milli>(end - start).count();
}

std::vector<glm::vec4> LlvmpipeRenderer::image() const {
    Gl& gl = impl_->gl;
    impl_->make_current();
    std::vector<glm::vec4> rgba(size_t(impl_->width) * size_t(impl_->height));
    gl.BindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
    if (impl_->samples > 1) {  // each pixel's samples averaged (in linear light for sRGB)
        gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, impl_->resolved_fbo);
        gl.BlitFramebuffer(0, 0, impl_->width, impl_->height, 0, 0, impl_->width, impl_->height,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
        gl.BindFramebuffer(GL_FRAMEBUFFER, impl_->resolved_fbo);
    }
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    // GL's row 0 holds the image's top row (clip_from_world).
    gl.ReadPixels(0, 0, impl_->width, impl_->height, GL_RGBA, GL_FLOAT, rgba.data());
    impl_->check_errors("image()");
    if (impl_->target == LlvmpipeTarget::srgb8)  // GL reads the stored codes: decode them
        for (glm::vec4& c : rgba)
            for (int k = 0; k < 3; ++k) c[k] = srgb8_to_linear(uint8_t(std::lround(c[k] * 255.0f)));
    return rgba;
}

std::vector<uint8_t> LlvmpipeRenderer::coverage() const {
    const std::vector<glm::vec4> rgba = image();
    std::vector<uint8_t> covered(rgba.size());
    for (size_t i = 0; i < rgba.size(); ++i) covered[i] = glm::vec3(rgba[i]) != glm::vec3(0.0f);
    return covered;
}

}  // namespace facet::bench
