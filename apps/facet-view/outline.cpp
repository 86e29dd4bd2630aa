#include "outline.hpp"

#include <algorithm>
#include <utility>

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
    alone.use_material(white_);
    mask.objects = {alone};
    renderer_.render(mask, mask_);

    const int w = settings.width, h = settings.height;
    if (rgba.size() != size_t(w) * h * 4 || mask_.width() != w || mask_.height() != h) return;
    // Which pixels the object covers (white on black, 8-bit sRGB, one sample
    // a pixel: read in place), and their bounds.
    inside_.assign(size_t(w) * h, 0);
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int y = 0; y < h; ++y) {
        const uint8_t* row = std::as_const(mask_).color_data() + size_t(y) * mask_.stride() * 4;
        for (int x = 0; x < w; ++x)
            if (row[size_t(x) * 4] > 127) {
                inside_[size_t(y) * w + x] = 1;
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    }
    if (x1 < 0) return;  // not on screen
    const auto inside = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < w && y < h && inside_[size_t(y) * w + x];
    };
    // Around each edge pixel (inside, with a neighbour outside), the pixels
    // outside within `width` of it take the outline's colour.
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            if (!inside(x, y) ||
                (inside(x - 1, y) && inside(x + 1, y) && inside(x, y - 1) && inside(x, y + 1)))
                continue;
            for (int dy = -width; dy <= width; ++dy)
                for (int dx = -width; dx <= width; ++dx) {
                    const int px = x + dx, py = y + dy;
                    if (dx * dx + dy * dy > width * width || px < 0 || py < 0 || px >= w ||
                        py >= h || inside(px, py))
                        continue;
                    uint8_t* p = &rgba[(size_t(py) * w + px) * 4];
                    p[0] = 255, p[1] = 160, p[2] = 30, p[3] = 255;
                }
        }
}

}  // namespace facet::view
