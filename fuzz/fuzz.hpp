// facet's fuzz targets: one function per target, shared by the libFuzzer
// programs (fuzz/main.cpp, built with FACET_FUZZ) and by the regression
// test that replays tests/fuzz_regressions/<target>/ in the normal build.
//
// Each function takes any bytes and returns normally when the code under
// test behaved: it either did its job, with every checked invariant holding,
// or it refused the input with a facet::Error. Anything else - another
// exception type, a broken invariant - throws Failure, which says what went
// wrong. Crashes, hangs and sanitizer reports are findings of their own.
//
//   scene_yaml     load_scene() on a scene file, then one tiny render
//   material_yaml  load_material() on a material file
//   mesh_import    load_mesh() on an OBJ or PLY file (assimp + ply_check)
//   raster         random clip-space triangles through Pipeline::draw,
//                  against an exact-geometry coverage oracle
//   texture_decode decode_texture() on an image file, then the per-path
//                  sampler against the reference on what it decoded
//   gltf           a glTF or GLB file: load_mesh(), its materials bound
//                  with their embedded images, its node animation posed
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace facet::fuzz {

// A broken rule: the test's finding, in words.
class Failure : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

void scene_yaml(const uint8_t* data, size_t size);
void material_yaml(const uint8_t* data, size_t size);
void mesh_import(const uint8_t* data, size_t size);
void raster(const uint8_t* data, size_t size);
void texture_decode(const uint8_t* data, size_t size);
void gltf(const uint8_t* data, size_t size);

}  // namespace facet::fuzz
