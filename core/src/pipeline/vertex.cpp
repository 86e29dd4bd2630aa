// The vertex stage (vertex.hpp).
#include "pipeline/vertex.hpp"

#include "pipeline/kernels.hpp"
#include "plugin/plugin_calls.hpp"

#include "facet/mesh.hpp"
#include "facet/plugin.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace facet {

namespace {

constexpr uint32_t kVertexBatch = 256;

template <class T>
const float* input(const ShaderPlugin& shader, facet_need need, const std::vector<T>& data,
                   size_t first) {
    if (!shader.needs(need) || data.empty()) return nullptr;
    return glm::value_ptr(data[first]);
}

}  // namespace

void shade_vertices(const Mesh& mesh, uint32_t first_vertex, uint32_t vertex_count,
                    const ShaderPlugin& shader, const Viewport& viewport, const Kernels& kernels,
                    ThreadPool& pool, QueuedDraw& d) {
    const size_t vcount = vertex_count;
    const uint32_t floats = shader.varying_floats();
    d.clip.resize(vcount);
    d.window.resize(vcount);
    d.varyings.resize(vcount * floats + 1);
    const int batches = int((vcount + kVertexBatch - 1) / kVertexBatch);
    pool.parallel_for(batches, [&](int b, int) {
        const size_t first = size_t(b) * kVertexBatch;  // of the draw's vertices
        const size_t in = first_vertex + first;         // of the mesh's
        const facet_vertex_batch batch{
            uint32_t(std::min<size_t>(kVertexBatch, vcount - first)),
            glm::value_ptr(mesh.positions[in]),
            input(shader, FACET_NEED_NORMALS, mesh.normals, in),
            input(shader, FACET_NEED_UVS, mesh.uvs, in),
            input(shader, FACET_NEED_COLORS, mesh.colors, in),
            input(shader, FACET_NEED_TANGENTS, mesh.tangents, in),
            glm::value_ptr(d.clip[first]),
            d.varyings.data() + first * floats,
            floats,
            input(shader, FACET_NEED_UV1, mesh.uvs1, in)};
        call_plugin(&shader, PluginEntry::vertex, shader.shader_desc().vertex, &d.abi, &batch);
        // Outcodes and window positions: once per vertex, however many
        // triangles share it.
        kernels.project_vertices(&d.clip[first], batch.count, viewport, &d.window[first]);
    });
}

}  // namespace facet
