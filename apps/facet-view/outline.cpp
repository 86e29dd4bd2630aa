#include "outline.hpp"

#include <algorithm>

namespace facet::view {

Outline::Outline(int threads) : renderer_(threads) {}

void Outline::draw(const Object& object, const Camera& camera, const RenderSettings& settings,
                   PluginRegistry& registry, TextureCache& textures, std::vector<uint8_t>& rgba,
                   int width) {
    if (!object.mesh || !object.visible) return;
    if (!white_) {
        auto m = std::make_shared<Material>();
        m->source = m->file = "(selection outline)";
        m->shader = "unlit";
        MaterialParam colour;
        colour.name = "base_color";
        colour.kind = MaterialParam::Kind::vector;
        colour.numbers = {1.0, 1.0, 1.0, 1.0};
        m->params = {colour};
        m->cull = CullMode::none;  // the silhouette from either side
        bind(*m, registry.get("unlit"), textures);
        white_ = m;
    }
    Scene mask;
    mask.camera = camera;
    mask.settings.width = settings.width;
    mask.settings.height = settings.height;
    mask.settings.reversed_z = settings.reversed_z;
    mask.settings.depth_compare = settings.depth_compare;
    mask.settings.front_ccw = settings.front_ccw;
    mask.settings.clear_color = glm::vec4(0.0f);
    mask.settings.shadows = mask.settings.ao = mask.settings.post = false;
    Object alone = object;
    alone.material = white_;
    mask.objects = {alone};
    renderer_.render(mask, mask_);
    renderer_.pipeline().resolve_srgb8(mask_, mask_rgba_);

    const int w = settings.width, h = settings.height;
    if (rgba.size() != size_t(w) * h * 4 || mask_rgba_.size() != rgba.size()) return;
    const auto inside = [&](int x, int y) { return mask_rgba_[(size_t(y) * w + x) * 4] > 127; };
    // The mask's bounds, widened by the band.
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (inside(x, y)) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    if (x1 < 0) return;  // not on screen
    x0 = std::max(0, x0 - width), y0 = std::max(0, y0 - width);
    x1 = std::min(w - 1, x1 + width), y1 = std::min(h - 1, y1 + width);
    // A pixel outside the object within `width` of one inside it.
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            if (inside(x, y)) continue;
            bool near = false;
            for (int dy = -width; dy <= width && !near; ++dy)
                for (int dx = -width; dx <= width && !near; ++dx) {
                    const int sx = x + dx, sy = y + dy;
                    near = sx >= 0 && sy >= 0 && sx < w && sy < h && dx * dx + dy * dy <= width * width &&
                           inside(sx, sy);
                }
            if (!near) continue;
            uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
            p[0] = 255, p[1] = 160, p[2] = 30, p[3] = 255;
        }
}

}  // namespace facet::view
