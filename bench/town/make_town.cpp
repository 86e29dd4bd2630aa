// facet-make-town OUTDIR: writes a textured town for facet-bench (its
// `town` scene): town.obj with town.mtl, 56 textures in textures/, and
// town.yaml, a scene that looks down one of its streets from eye height.
//
// The town is what a textured scene a user brings looks like to a
// renderer: about 100k triangles in many parts, each of its 56 materials
// with a colour texture of its own (the MTL's map_Kd, drawn by phong),
// sizes from 128 to 1024 texels and some not powers of two, everything
// mipmapped and filtered trilinearly, seen at grazing angles (the street,
// the facades) and up close. Streets and blocks on a 10 x 10 grid;
// buildings with facades of windows, cornices and domes; trees; cars.
// The same bytes on every run (its own hash, no clock), in well under a
// second; the build writes it into its own tree (bench/CMakeLists.txt).
#include <glm/glm.hpp>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// ---- a deterministic hash, for every random choice ----------------------

uint32_t hash(uint32_t a, uint32_t b = 0, uint32_t c = 0) {
    uint32_t h = 0x9E3779B9u ^ a;
    for (uint32_t k : {b, c, 0x85EBCA6Bu}) {
        h = (h ^ k) * 0x85EBCA6Bu;
        h ^= h >> 13;
        h *= 0xC2B2AE35u;
        h ^= h >> 16;
    }
    return h;
}
float unit(uint32_t a, uint32_t b = 0, uint32_t c = 0) {
    return float(hash(a, b, c) >> 8) / 16777216.0f;
}

// ---- textures -------------------------------------------------------------

struct Image {
    int width, height;
    std::vector<uint8_t> rgba;
    void set(int x, int y, glm::vec3 c) {
        uint8_t* p = &rgba[size_t(y * width + x) * 4];
        for (int k = 0; k < 3; ++k) p[k] = uint8_t(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
        p[3] = 255;
    }
};

// Smooth value noise in [0, 1] on a lattice of `cells` that wraps.
float noise(float x, float y, int cells, uint32_t seed) {
    const int ix = int(std::floor(x)), iy = int(std::floor(y));
    float fx = x - float(ix), fy = y - float(iy);
    fx = fx * fx * (3 - 2 * fx), fy = fy * fy * (3 - 2 * fy);
    const auto at = [&](int i, int j) {
        return unit(uint32_t((i % cells + cells) % cells), uint32_t((j % cells + cells) % cells),
                    seed);
    };
    const float top = at(ix, iy) + (at(ix + 1, iy) - at(ix, iy)) * fx;
    const float bottom = at(ix, iy + 1) + (at(ix + 1, iy + 1) - at(ix, iy + 1)) * fx;
    return top + (bottom - top) * fy;
}

// A colour from a seed: a hue around `base`, varied.
glm::vec3 tint(glm::vec3 base, uint32_t seed, float spread) {
    return base *
           (1.0f - spread + 2.0f * spread * glm::vec3(unit(seed, 1), unit(seed, 2), unit(seed, 3)));
}

using Pattern = std::function<glm::vec3(float u, float v, int x, int y)>;

Image paint(int width, int height, const Pattern& pattern) {
    Image image{width, height, std::vector<uint8_t>(size_t(width * height) * 4)};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.set(
                x, y,
                pattern((float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height), x, y));
    return image;
}

// A facade of `floors` x `columns` windows over a wall (brick or render),
// some windows lit.
Image facade(int size_x, int size_y, uint32_t seed) {
    const int floors = 4, columns = 4;
    const glm::vec3 wall = tint({0.62f, 0.5f, 0.42f}, seed, 0.35f);
    const bool brick = seed % 2 == 0;
    return paint(size_x, size_y, [&](float u, float v, int, int) {
        const float fu = u * float(columns), fv = v * float(floors);
        const int cu = int(fu), cv = int(fv);
        const float wu = fu - float(cu), wv = fv - float(cv);
        if (wu > 0.22f && wu < 0.78f && wv > 0.25f && wv < 0.8f) {
            const bool lit = unit(seed, uint32_t(cu), uint32_t(cv)) < 0.3f;
            const float frame =
                (std::abs(wu - 0.5f) < 0.02f || std::abs(wv - 0.52f) < 0.02f) ? 0.3f : 1.0f;
            return (lit ? glm::vec3(0.95f, 0.82f, 0.5f)
                        : glm::vec3(0.12f, 0.16f, 0.22f) * (0.6f + wv)) *
                   frame;
        }
        float shade = 0.85f + 0.15f * noise(u * 32.0f, v * 32.0f, 32, seed);
        if (brick) {
            const float row = v * 64.0f, course = std::floor(row);
            const float col = u * 16.0f + (int(course) % 2 ? 0.5f : 0.0f);
            if (row - course < 0.12f || col - std::floor(col) < 0.06f) shade *= 0.7f;
        }
        return wall * shade;
    });
}

Image asphalt(int size, uint32_t seed, bool lines) {
    return paint(size, size, [&](float u, float v, int, int) {
        const float n =
            0.8f * noise(u * 64, v * 64, 64, seed) + 0.2f * noise(u * 8, v * 8, 8, seed + 1);
        glm::vec3 c = glm::vec3(0.16f, 0.16f, 0.17f) * (0.75f + 0.5f * n);
        if (lines && std::abs(u - 0.5f) < 0.012f && std::fmod(v * 4.0f, 1.0f) < 0.55f)
            c = glm::vec3(0.85f, 0.8f, 0.55f);
        return c;
    });
}

Image tiles(int size_x, int size_y, uint32_t seed, glm::vec3 base, float count) {
    return paint(size_x, size_y, [&](float u, float v, int, int) {
        const float tu = u * count, tv = v * count;
        const bool grout = tu - std::floor(tu) < 0.06f || tv - std::floor(tv) < 0.06f;
        const float n = unit(seed, uint32_t(tu), uint32_t(tv));
        return grout ? base * 0.45f
                     : base * (0.8f + 0.3f * n) * (0.9f + 0.1f * noise(u * 16, v * 16, 16, seed));
    });
}

Image speckle(int size_x, int size_y, uint32_t seed, glm::vec3 base, float scale) {
    return paint(size_x, size_y, [&](float u, float v, int, int) {
        const float n = noise(u * scale, v * scale, int(scale), seed) * 0.6f +
                        noise(u * scale * 4, v * scale * 4, int(scale) * 4, seed + 7) * 0.4f;
        return base * (0.55f + 0.9f * n);
    });
}

Image stripes(int size, uint32_t seed, glm::vec3 base, float count) {
    return paint(size, size, [&](float u, float v, int, int) {
        const float s = std::sin((u + 0.3f * v) * count * 6.2831853f);
        return base * (0.8f + 0.2f * s) * (0.9f + 0.2f * noise(u * 16, v * 16, 16, seed));
    });
}

// ---- the mesh -------------------------------------------------------------

struct Obj {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::map<std::string, std::vector<glm::ivec3>> faces;  // per material: corner index triples
    size_t triangles = 0;

    int vertex(glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
        positions.push_back(p);
        normals.push_back(n);
        uvs.push_back(uv);
        return int(positions.size());  // OBJ counts from 1
    }
    void triangle(const std::string& material, int a, int b, int c) {
        faces[material].push_back({a, b, c});
        ++triangles;
    }
    // A quad a b c d (counter-clockwise seen from outside), its UVs from
    // its size in metres times `texels_per_metre` repeats, and as one picture
    // where `whole` (a facade).
    void quad(const std::string& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
              float repeat_u, float repeat_v) {
        const glm::vec3 n = glm::normalize(glm::cross(b - a, d - a));
        const int i = vertex(a, n, {0, repeat_v}), j = vertex(b, n, {repeat_u, repeat_v});
        const int k = vertex(c, n, {repeat_u, 0}), l = vertex(d, n, {0, 0});
        triangle(m, i, j, k);
        triangle(m, i, k, l);
    }
    // An axis-aligned box on the ground from lo to hi: sides with `side`
    // (u repeats every `metres_u`), top with `top`.
    void box(glm::vec3 lo, glm::vec3 hi, const std::string& side, const std::string& top,
             float metres_u, float metres_v) {
        const glm::vec3 s = hi - lo;
        const auto ru = [&](float w) { return std::max(1.0f, std::round(w / metres_u)); };
        const float rv = std::max(1.0f, std::round(s.y / metres_v));
        quad(side, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z},
             ru(s.x), rv);
        quad(side, {hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z},
             ru(s.x), rv);
        quad(side, {hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z},
             ru(s.z), rv);
        quad(side, {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z},
             ru(s.z), rv);
        quad(top, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
             s.x / 4, s.z / 4);
    }
    // A sphere (or its top half) of `rings` x 2 `rings` quads.
    void sphere(const std::string& m, glm::vec3 centre, glm::vec3 radii, int rings, bool dome) {
        const int segments = 2 * rings, first = dome ? rings / 2 : 0;
        std::vector<int> index;
        for (int r = first; r <= rings; ++r)
            for (int s = 0; s <= segments; ++s) {
                const float theta = 3.14159265f * float(r) / float(rings);
                const float phi = 6.2831853f * float(s) / float(segments);
                const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                                  -std::sin(theta) * std::sin(phi));
                index.push_back(
                    vertex(centre + n * radii, glm::normalize(n / radii),
                           {2.0f * float(s) / float(segments), 2.0f * float(r) / float(rings)}));
            }
        const int row = segments + 1;
        for (int r = 0; r < rings - first; ++r)
            for (int s = 0; s < segments; ++s) {
                const int a = index[size_t(r * row + s)], b = index[size_t(r * row + s + 1)];
                const int c = index[size_t((r + 1) * row + s + 1)],
                          d = index[size_t((r + 1) * row + s)];
                triangle(m, a, d, c);
                triangle(m, a, c, b);
            }
    }
    void cylinder(const std::string& m, glm::vec3 base, float radius, float height, int segments) {
        for (int s = 0; s < segments; ++s) {
            const float a0 = 6.2831853f * float(s) / float(segments),
                        a1 = 6.2831853f * float(s + 1) / float(segments);
            const glm::vec3 p0 = base + radius * glm::vec3(std::cos(a0), 0, -std::sin(a0));
            const glm::vec3 p1 = base + radius * glm::vec3(std::cos(a1), 0, -std::sin(a1));
            quad(m, p0, p1, p1 + glm::vec3(0, height, 0), p0 + glm::vec3(0, height, 0),
                 1.0f / float(segments) * 4, height);
        }
    }
};

// ---- the town ------------------------------------------------------------

struct Material {
    std::string name;
    Image texture;
    glm::vec3 specular{0.1f};
    float shininess = 16.0f;
};

std::vector<Material> make_materials() {
    std::vector<Material> m;
    const int facade_sizes[][2] = {{512, 512},  {256, 512}, {384, 384},
                                   {512, 1024}, {320, 480}, {256, 256}};
    for (uint32_t i = 0; i < 24; ++i)
        m.push_back({"facade" + std::to_string(i),
                     facade(facade_sizes[i % 6][0], facade_sizes[i % 6][1], 100 + i)});
    m.push_back({"road", asphalt(1024, 1, true), glm::vec3(0.05f), 8});
    m.push_back({"asphalt", asphalt(512, 2, false), glm::vec3(0.05f), 8});
    m.push_back({"pavement", tiles(256, 256, 3, {0.6f, 0.58f, 0.55f}, 8), glm::vec3(0.1f), 12});
    m.push_back({"plaza", tiles(384, 384, 4, {0.7f, 0.55f, 0.45f}, 12), glm::vec3(0.15f), 20});
    m.push_back({"grass", speckle(256, 256, 5, {0.25f, 0.45f, 0.15f}, 16), glm::vec3(0.02f), 4});
    m.push_back({"gravel", speckle(128, 128, 6, {0.5f, 0.47f, 0.42f}, 32), glm::vec3(0.05f), 6});
    for (uint32_t i = 0; i < 6; ++i)
        m.push_back({"roof" + std::to_string(i),
                     tiles(256, 256, 200 + i, tint({0.45f, 0.3f, 0.25f}, 210 + i, 0.4f), 16)});
    for (uint32_t i = 0; i < 4; ++i)
        m.push_back({"cornice" + std::to_string(i),
                     speckle(128, 128, 300 + i, tint({0.8f, 0.78f, 0.7f}, 310 + i, 0.2f), 8)});
    for (uint32_t i = 0; i < 3; ++i)
        m.push_back({"dome" + std::to_string(i),
                     tiles(256, 256, 400 + i, tint({0.3f, 0.5f, 0.45f}, 410 + i, 0.4f), 24),
                     glm::vec3(0.5f), 64});
    for (uint32_t i = 0; i < 2; ++i)
        m.push_back({"bark" + std::to_string(i), stripes(128, 500 + i, {0.35f, 0.25f, 0.18f}, 12)});
    for (uint32_t i = 0; i < 3; ++i)
        m.push_back({"leaves" + std::to_string(i),
                     speckle(256, 256, 600 + i, tint({0.2f, 0.42f, 0.15f}, 610 + i, 0.3f), 32)});
    for (uint32_t i = 0; i < 8; ++i)
        m.push_back({"car" + std::to_string(i),
                     stripes(128, 700 + i, tint({0.6f, 0.3f, 0.3f}, 710 + i, 0.8f), 2),
                     glm::vec3(0.6f), 80});
    return m;
}

constexpr int kBlocks = 10;       // blocks a side
constexpr float kBlock = 40.0f;   // metres a block, street included
constexpr float kStreet = 12.0f;  // metres of street between blocks

// Streets (textured asphalt with lines along the long axis), pavements and
// the blocks' ground, as a grid of 4 m cells: many small triangles, as a
// scanned or modelled ground has.
void ground(Obj& obj) {
    const float size = kBlocks * kBlock, cell = 4.0f;
    const int cells = int(size / cell);
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const float x = float(i) * cell - size / 2, z = float(j) * cell - size / 2;
            const float bx = std::fmod(x + size / 2, kBlock), bz = std::fmod(z + size / 2, kBlock);
            const bool street_x = bx < kStreet, street_z = bz < kStreet;
            std::string m = "grass";
            if (street_x && street_z)
                m = "asphalt";
            else if (street_x || street_z)
                m = "road";
            else if (bx < kStreet + 3 || bz < kStreet + 3 || bx > kBlock - 3 || bz > kBlock - 3)
                m = "pavement";
            else if (hash(uint32_t(i / 8), uint32_t(j / 8), 9) % 3 == 0)
                m = "plaza";
            else if (hash(uint32_t(i / 8), uint32_t(j / 8), 10) % 5 == 0)
                m = "gravel";
            // A road's line runs along its street, whichever way that is.
            const bool along_x = street_z && !street_x;
            const auto uv = [&](float px, float pz) {
                const float across = std::fmod((along_x ? pz : px) + size / 2, kBlock) / kStreet;
                const float along = (along_x ? px : pz) / 8.0f;
                return m == "road" ? glm::vec2(across, along) : glm::vec2(px, pz) / 4.0f;
            };
            const glm::vec3 n(0, 1, 0);
            const float x1 = x + cell, z1 = z + cell;
            const int ia = obj.vertex({x, 0, z1}, n, uv(x, z1)),
                      ib = obj.vertex({x1, 0, z1}, n, uv(x1, z1));
            const int ic = obj.vertex({x1, 0, z}, n, uv(x1, z)),
                      id = obj.vertex({x, 0, z}, n, uv(x, z));
            obj.triangle(m, ia, ib, ic);
            obj.triangle(m, ia, ic, id);
        }
}

void buildings(Obj& obj) {
    for (int bj = 0; bj < kBlocks; ++bj)
        for (int bi = 0; bi < kBlocks; ++bi) {
            const float x0 = float(bi) * kBlock - kBlocks * kBlock / 2 + kStreet + 4;
            const float z0 = float(bj) * kBlock - kBlocks * kBlock / 2 + kStreet + 4;
            const float span = kBlock - kStreet - 8;
            for (int k = 0; k < 4; ++k) {  // a building in each corner of the block
                const uint32_t h = hash(uint32_t(bi), uint32_t(bj), uint32_t(k));
                if (h % 7 == 0) continue;  // an empty lot
                const float w = span / 2 - 1, x = x0 + float(k % 2) * (span / 2 + 1),
                            z = z0 + float(k / 2) * (span / 2 + 1);
                const float height = 8.0f + float(h % 6) * 4.0f;
                const std::string facade = "facade" + std::to_string(h % 24);
                obj.box({x, 0, z}, {x + w, height, z + w}, facade, "roof" + std::to_string(h % 6),
                        16.0f, 16.0f);
                const std::string cornice = "cornice" + std::to_string(h % 4);
                obj.box({x - 0.3f, height, z - 0.3f}, {x + w + 0.3f, height + 0.6f, z + w + 0.3f},
                        cornice, cornice, 1, 1);
                if (h % 5 == 0)
                    obj.sphere("dome" + std::to_string(h % 3),
                               {x + w / 2, height + 0.6f, z + w / 2}, glm::vec3(w / 3), 16, true);
            }
        }
}

void trees_and_cars(Obj& obj) {
    for (int bj = 0; bj < kBlocks; ++bj)
        for (int bi = 0; bi < kBlocks; ++bi) {
            const float x0 = float(bi) * kBlock - kBlocks * kBlock / 2,
                        z0 = float(bj) * kBlock - kBlocks * kBlock / 2;
            for (int t = 0; t < 4; ++t) {  // along the pavement of the street in x
                const glm::vec3 at(x0 + kStreet + 1.5f, 0, z0 + kStreet + 4 + float(t) * 6.5f);
                const uint32_t h = hash(uint32_t(bi), uint32_t(bj), uint32_t(t) + 20);
                obj.cylinder("bark" + std::to_string(h % 2), at, 0.2f, 2.5f, 8);
                obj.sphere("leaves" + std::to_string(h % 3), at + glm::vec3(0, 3.6f, 0),
                           {1.5f, 1.8f, 1.5f}, 6, false);
            }
            for (int c = 0; c < 2; ++c) {  // parked along the street in z
                const uint32_t h = hash(uint32_t(bi), uint32_t(bj), uint32_t(c) + 40);
                const glm::vec3 at(x0 + 2.5f + float(c % 2) * 6.0f, 0,
                                   z0 + kStreet + 6 + float(h % 20));
                const std::string paint = "car" + std::to_string(h % 8);
                obj.box(at + glm::vec3(0, 0.3f, 0), at + glm::vec3(1.8f, 1.1f, 4.2f), paint, paint,
                        2, 1);
                obj.box(at + glm::vec3(0.15f, 1.1f, 1.0f), at + glm::vec3(1.65f, 1.6f, 3.2f), paint,
                        paint, 2, 1);
            }
        }
}

void write_obj(const Obj& obj, const fs::path& path) {
    std::ofstream out(path);
    out << "# A textured town for facet-bench, written by facet-make-town.\nmtllib town.mtl\n";
    char line[128];
    for (const glm::vec3& p : obj.positions)
        out.write(line, std::snprintf(line, sizeof line, "v %.4f %.4f %.4f\n", p.x, p.y, p.z));
    for (const glm::vec2& t : obj.uvs)
        out.write(line, std::snprintf(line, sizeof line, "vt %.5f %.5f\n", t.x, t.y));
    for (const glm::vec3& n : obj.normals)
        out.write(line, std::snprintf(line, sizeof line, "vn %.4f %.4f %.4f\n", n.x, n.y, n.z));
    for (const auto& [material, faces] : obj.faces) {
        out << "g " << material << "\nusemtl " << material << "\n";
        for (const glm::ivec3& f : faces)
            out.write(line, std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", f.x,
                                          f.x, f.x, f.y, f.y, f.y, f.z, f.z, f.z));
    }
}

void write_materials(const std::vector<Material>& materials, const fs::path& folder) {
    fs::create_directories(folder / "textures");
    std::ofstream mtl(folder / "town.mtl");
    for (const Material& m : materials) {
        const std::string file = "textures/" + m.name + ".png";
        const Image& t = m.texture;
        if (!stbi_write_png((folder / file).string().c_str(), t.width, t.height, 4, t.rgba.data(),
                            t.width * 4))
            throw std::runtime_error("cannot write " + (folder / file).string());
        mtl << "newmtl " << m.name << "\nKd 1 1 1\nKs " << m.specular.x << ' ' << m.specular.y
            << ' ' << m.specular.z << "\nNs " << m.shininess << "\nmap_Kd " << file << "\n\n";
    }
}

void write_scene(const fs::path& path) {
    std::ofstream out(path);
    out << R"(# A textured town (facet-make-town): about 100k triangles in 56 parts, each
# with its own colour texture (128 to 1024 texels, some not powers of two),
# trilinear, seen from eye height down a street in the late afternoon sun.
camera:
  position: [-34, 1.7, -150]
  target: [-34, 1.2, 0]
  fov_y: 60
  near: 0.1
  far: 500
render:
  size: [1920, 1080]
  clear_color: [0.55, 0.65, 0.8, 1]
  cull: back
lights:
  - {type: directional, direction: [-0.45, -0.7, 0.4], color: [1.0, 0.93, 0.82], intensity: 1.6}
objects:
  - name: town
    mesh: town.obj
)";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: facet-make-town OUTDIR\n");
        return 2;
    }
    try {
        const fs::path folder = argv[1];
        fs::create_directories(folder);
        Obj obj;
        ground(obj);
        buildings(obj);
        trees_and_cars(obj);
        const std::vector<Material> materials = make_materials();
        write_materials(materials, folder);
        write_obj(obj, folder / "town.obj");
        write_scene(folder / "town.yaml");
        std::printf("facet-make-town: %zu triangles, %zu materials in %s\n", obj.triangles,
                    materials.size(), folder.string().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet-make-town: %s\n", e.what());
        return 1;
    }
    return 0;
}
