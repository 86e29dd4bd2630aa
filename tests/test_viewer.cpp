// facet-view, driven as a user would: synthetic SDL events into a real
// window (under Xvfb in CI), files edited and shaders recompiled while it
// runs, and the scripted command line against facet-render.
//
// Run through `xvfb-run` by CTest; the camera controller tests need no
// display.
#include "support.hpp"
#include "editor.hpp"
#include "viewer.hpp"

#include <facet/error.hpp>
#include <facet/isa.hpp>

#include <catch2/catch.hpp>

#include <stb/stb_image.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

using namespace facet;
using namespace facet::view;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

using test::write;

void push(SDL_Event e) { REQUIRE(SDL_PushEvent(&e) == 1); }

void key(SDL_Keycode sym, bool down = true, Uint16 mod = KMOD_NONE) {
    SDL_Event e{};
    e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
    e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.sym = sym;
    e.key.keysym.mod = mod;
    push(e);
    if (down) key(sym, false, mod);
}

void drag(int dx, int dy, Uint32 buttons) {
    SDL_Event e{};
    e.type = SDL_MOUSEMOTION;
    e.motion.state = buttons;
    e.motion.xrel = dx;
    e.motion.yrel = dy;
    push(e);
}

float distance(const Camera& c) { return glm::length(c.position - c.target); }

// A viewer on the default scene (or `scene`), small and on one thread.
Options small(const std::string& scene = "") {
    Options o;
    o.scene = scene;
    o.size = glm::ivec2(160, 90);
    o.threads = 1;
    static const test::TempDir shots("shots");  // shared by the tests that do not count them
    o.screenshots = shots.path;
    return o;
}

// Pumps until `done` or `timeout`; true if done.
template <class Done>
bool pump_until(Viewer& v, Done done, std::chrono::milliseconds timeout = 10s) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        v.pump();
        if (done()) return true;
        std::this_thread::sleep_for(10ms);
    }
    return false;
}

bool has_message(const Viewer& v, const std::string& part, bool error) {
    for (const Message& m : v.messages())
        if (m.error == error && m.text.find(part) != std::string::npos) return true;
    return false;
}

// Compiles the test plugin as shader `name` filling red `red`, appearing
// whole at `out` as a build's output does.
bool compile_plugin(const fs::path& out, const std::string& name, float red) {
    const fs::path tmp = out.string() + ".tmp";
    if (!test::compile_plugin(tmp, name, "-DFILL_RED=" + std::to_string(red) + "f")) return false;
    fs::rename(tmp, out);
    return true;
}

}  // namespace

TEST_CASE("orbit keeps the distance to the target and stops short of the poles", "[camera]") {
    Camera home;
    home.position = {0, 1, 4};
    home.target = {0, 1, 0};
    CameraController c(home);
    c.orbit(90, 0);
    CHECK(distance(c.camera()) == Approx(4.0f));
    CHECK(c.camera().position.x == Approx(4.0f).margin(1e-5));  // a quarter turn about +y
    c.orbit(0, 200);
    const glm::vec3 d = glm::normalize(c.camera().position - c.camera().target);
    CHECK(glm::degrees(std::asin(d.y)) == Approx(89.0f).margin(1e-3));
    CHECK(distance(c.camera()) == Approx(4.0f));
    c.reset();
    CHECK(c.camera().position == home.position);
}

TEST_CASE("pan moves camera and target together; zoom scales the distance", "[camera]") {
    Camera home;
    home.position = {0, 0, 5};
    home.target = {0, 0, 0};
    home.fov_y = 90.0f;  // the view is 2 * 5 units tall at the target
    CameraController c(home);
    c.pan(50, 0, 100);  // half the view's height, dragged right: the camera goes left
    CHECK(c.camera().position.x == Approx(-5.0f));
    CHECK(c.camera().target.x == Approx(-5.0f));
    CHECK(distance(c.camera()) == Approx(5.0f));
    c.zoom(2);
    CHECK(distance(c.camera()) == Approx(5.0f * 0.81f));
    c.zoom(-2);
    CHECK(distance(c.camera()) == Approx(5.0f));
}

TEST_CASE("fly moves along the view at its speed and looks around in place", "[camera]") {
    Camera home;
    home.position = {0, 0, 5};
    home.target = {0, 0, 0};
    CameraController c(home);
    CHECK(c.speed() == Approx(5.0f));  // crosses the distance to the target in a second
    c.fly({0, 0, 1}, 0.5f);
    CHECK(c.camera().position.z == Approx(2.5f));
    c.fly({0, 1, 0}, 0.2f);
    CHECK(c.camera().position.y == Approx(1.0f));
    c.faster();
    CHECK(c.speed() == Approx(7.5f));
    const glm::vec3 eye = c.camera().position;
    c.look(90, 0);
    CHECK(c.camera().position == eye);
    const glm::vec3 forward = glm::normalize(c.camera().target - eye);
    CHECK(forward.x == Approx(-1.0f).margin(1e-5));  // positive yaw turns left
}

TEST_CASE("the viewer renders once, then only when something changes", "[viewer]") {
    Viewer v(small());
    v.pump();
    REQUIRE(v.frames_rendered() == 1);
    for (int i = 0; i < 20; ++i) v.pump();
    CHECK(v.frames_rendered() == 1);  // idle: nothing rendered
    CHECK(v.wait_ms() == -1);         // and run() would sleep until an event
    CHECK(v.overlay().stats.triangles_in == 5856);  // Spot
    // The overlay names the instruction-set path the frame was drawn on.
    CHECK(v.overlay().isa == default_isa());
    CHECK(stats_text(v.overlay()).find(std::string(isa_name(default_isa())) + "\n") !=
          std::string::npos);
    drag(5, 0, 0);  // a move without a button changes nothing
    v.pump();
    CHECK(v.frames_rendered() == 1);
}

TEST_CASE("an orbit drag and the wheel move the camera and render again", "[viewer]") {
    Viewer v(small());
    v.pump();
    const Camera before = v.controller().camera();
    const std::vector<uint8_t> image = v.shown();
    drag(40, 10, SDL_BUTTON_LMASK);
    v.pump();
    const Camera after = v.controller().camera();
    CHECK(after.position != before.position);
    CHECK(distance(after) == Approx(distance(before)));
    CHECK(v.frames_rendered() == 2);
    CHECK(v.shown() != image);
    SDL_Event wheel{};
    wheel.type = SDL_MOUSEWHEEL;
    wheel.wheel.y = 1;
    push(wheel);
    v.pump();
    CHECK(distance(v.controller().camera()) == Approx(0.9f * distance(before)));
    key(SDLK_r);
    v.pump();
    CHECK(v.controller().camera().position == before.position);
}

TEST_CASE("a frame where nothing the shadows depend on changed draws no shadow map, and the "
          "overlay says so",
          "[viewer][shadow]") {
    Viewer v(small((fs::path(FACET_SOURCE_DIR) / "configs/scenes/shadow.yaml").string()));
    v.pump();
    CHECK(v.overlay().stats.shadow_passes == 2);
    CHECK(stats_text(v.overlay()).find("shadow maps unchanged") == std::string::npos);
    key(SDLK_l);  // wireframe: a new frame, the same shadow maps
    v.pump();
    REQUIRE(v.frames_rendered() == 2);
    CHECK(v.overlay().stats.shadow_passes == 0);
    CHECK(v.overlay().stats.shadow_maps_reused == 2);
    CHECK(stats_text(v.overlay()).find("2 shadow maps unchanged") != std::string::npos);
    drag(40, 10, SDL_BUTTON_LMASK);  // the camera moves: the sun's map follows the view
    v.pump();
    CHECK(v.overlay().stats.shadow_passes == 1);
    CHECK(v.overlay().stats.shadow_maps_reused == 1);
}

TEST_CASE("the overlay times each pass of the post chain; key 3 turns the chain off",
          "[viewer][post]") {
    Viewer v(small((fs::path(FACET_SOURCE_DIR) / "configs/scenes/post.yaml").string()));
    v.pump();
    CHECK(v.overlay().stats.post_passes == 3);
    const std::string text = stats_text(v.overlay());
    for (const char* pass : {" bloom ", " tonemap ", " fxaa "}) {
        INFO(pass);
        CHECK(text.find(pass) != std::string::npos);
    }
    CHECK(text.find("post chain (off)") == std::string::npos);
    key(SDLK_3);
    v.pump();
    CHECK(v.overlay().stats.post_passes == 0);
    CHECK(stats_text(v.overlay()).find("post chain (off)") != std::string::npos);
}

TEST_CASE("keys cycle materials and toggle wireframe, MSAA, passes and the overlay", "[viewer]") {
    Viewer v(small());
    v.pump();
    const std::string first = v.scene().objects[0].material->source;
    const std::vector<uint8_t> plain = v.shown();
    key(SDLK_m);
    v.pump();
    const std::string second = v.scene().objects[0].material->source;
    CHECK(second != first);
    CHECK(fs::path(second).parent_path() ==
          fs::weakly_canonical(fs::path(FACET_SOURCE_DIR) / "configs/materials"));
    CHECK(v.frames_rendered() == 2);
    key(SDLK_m, true, KMOD_LSHIFT);  // and back
    v.pump();
    CHECK(fs::weakly_canonical(v.scene().objects[0].material->source) ==
          fs::weakly_canonical(first));

    key(SDLK_l);
    v.pump();
    CHECK(v.settings().wireframe);
    CHECK(v.shown() != plain);
    key(SDLK_n);
    v.pump();
    CHECK(v.framebuffer().samples() == 2);
    key(SDLK_1);
    key(SDLK_2);
    v.pump();
    CHECK_FALSE(v.settings().shadows);
    CHECK_FALSE(v.settings().ao);
    CHECK(v.overlay().settings.msaa == 2);

    // The overlay and the selection's outline are drawn over the image; O
    // hides the one, E (the editor) the other.
    CHECK(v.shown() != v.framebuffer().resolve_srgb8());
    key(SDLK_o);
    v.pump();
    CHECK_FALSE(v.overlay_visible());
    CHECK(v.shown() != v.framebuffer().resolve_srgb8());
    key(SDLK_e);
    v.pump();
    CHECK_FALSE(v.editor().visible());
    CHECK(v.shown() == v.framebuffer().resolve_srgb8());
    const uint64_t frames = v.frames_rendered();
    key(SDLK_h);
    v.pump();
    CHECK(v.help_visible());
    CHECK(v.frames_rendered() == frames);  // help is overlay only: no new render
}

TEST_CASE("fly mode moves while a key is held, and stops when it is released", "[viewer]") {
    Viewer v(small());
    v.pump();
    key(SDLK_f);
    v.pump();
    const glm::vec3 start = v.controller().camera().position;
    SDL_Event down{};
    down.type = SDL_KEYDOWN;
    down.key.keysym.sym = SDLK_w;
    push(down);
    v.pump();
    std::this_thread::sleep_for(50ms);
    v.pump();
    const glm::vec3 moved = v.controller().camera().position;
    CHECK(glm::length(moved - start) > 0.0f);
    SDL_Event up = down;
    up.type = SDL_KEYUP;
    push(up);
    v.pump();
    const uint64_t frames = v.frames_rendered();
    std::this_thread::sleep_for(30ms);
    v.pump();
    CHECK(v.frames_rendered() == frames);
}

TEST_CASE("P saves a screenshot named by time", "[viewer]") {
    const test::TempDir folder("shots");
    Options o = small();
    o.screenshots = folder.path;
    const fs::path& dir = folder.path;
    Viewer v(o);
    v.pump();
    key(SDLK_p);
    v.pump();
    int pngs = 0;
    for (const auto& e : fs::directory_iterator(dir))
        pngs += e.path().extension() == ".png" && e.path().filename().string().rfind("facet-", 0) == 0;
    CHECK(pngs == 1);
    CHECK(has_message(v, "saved", false));
}

TEST_CASE("bad input shows an error and keeps the last good state", "[viewer][bad]") {
    Viewer v(small("/no/such/scene.yaml"));  // falls back to the default scene
    v.pump();
    CHECK(has_message(v, "/no/such/scene.yaml: file not found", true));
    REQUIRE(v.scene().objects.size() == 1);

    const test::TempDir folder("view-bad");
    const fs::path& dir = folder.path;
    write(dir / "broken.yaml", "camera: {position: [0, 0, 1}\n");
    SDL_Event drop{};
    drop.type = SDL_DROPFILE;
    drop.drop.file = SDL_strdup((dir / "broken.yaml").c_str());
    push(drop);
    v.pump();
    CHECK(has_message(v, "broken.yaml:1:", true));
    CHECK(fs::equivalent(v.scene().source, fs::path(FACET_SOURCE_DIR) / "configs/default.yaml"));
}

TEST_CASE("an edited material re-renders; a broken one is refused and the image stays",
          "[viewer][reload]") {
    const test::TempDir folder("view-reload");
    const fs::path& dir = folder.path;
    write(dir / "quad.obj", test::kQuadObj);
    write(dir / "material.yaml", "shader: unlit\nparams: {base_color: [1, 0, 0, 1]}\n");
    write(dir / "scene.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
                              "objects:\n  - {mesh: quad.obj, material: material.yaml}\n");
    Viewer v(small((dir / "scene.yaml").string()));
    v.pump();
    REQUIRE(v.framebuffer().pixel(80, 45).r == Approx(1.0f));
    // Each version has a different size, so a watcher polling sizes and
    // coarse timestamps sees every change too.
    write(dir / "material.yaml", "shader: unlit\nparams: {base_color: [0, 1, 0, 1.0]}\n");
    REQUIRE(pump_until(v, [&] { return v.framebuffer().pixel(80, 45).g > 0.99f; }));
    CHECK(has_message(v, "reloaded", false));
    const uint64_t frames = v.frames_rendered();
    write(dir / "material.yaml", "shader: unlit\nparams: {base_color: [0, 0, 1, 1.00}\n");
    REQUIRE(pump_until(v, [&] { return has_message(v, "keeping the previous version", true); }));
    CHECK(v.frames_rendered() == frames);
    CHECK(v.framebuffer().pixel(80, 45).g > 0.99f);
}

TEST_CASE("a recompiled shader appears in the running viewer", "[viewer][reload]") {
    const test::TempDir folder("view-shader");
    const fs::path& dir = folder.path;
    fs::create_directories(dir / "plugins");
    REQUIRE(compile_plugin(dir / "plugins/hot.so", "hot", 0.25f));
    write(dir / "quad.obj", test::kQuadObj);
    write(dir / "scene.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
                              "plugin_paths: [plugins]\n"
                              "objects:\n  - {mesh: quad.obj, material: {shader: hot}}\n");
    Viewer v(small((dir / "scene.yaml").string()));
    v.pump();
    // The viewer draws into 8-bit sRGB: 0.25 is the code nearest to it.
    REQUIRE(v.framebuffer().pixel(80, 45).r == srgb8_to_linear(linear_to_srgb8(0.25f)));
    REQUIRE(compile_plugin(dir / "plugins/hot.so", "hot", 0.75f));
    REQUIRE(pump_until(v, [&] { return v.framebuffer().pixel(80, 45).r > 0.7f; }));
    CHECK(has_message(v, "reloaded shader 'hot'", false));
}

TEST_CASE("a shader that stalls gives up its frame, and the last good frame stays",
          "[viewer][reload]") {
    // As facet-view sets it, with a short limit (the test program's own).
    watch_plugin_calls({1000ms, PluginWatchdog::OnStall::abandon_frame});
    const test::TempDir folder("view-stall");
    const fs::path& dir = folder.path;
    fs::create_directories(dir / "plugins");
    REQUIRE(test::compile_plugin(dir / "plugins/stall.so", "stall",
                                 "-DWITH_GAIN -DLOOP_ABOVE_GAIN"));
    write(dir / "quad.obj", test::kQuadObj);
    write(dir / "material.yaml", "shader: stall\nparams: {gain: 0.5}\n");
    write(dir / "scene.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
                              "plugin_paths: [plugins]\n"
                              "objects:\n  - {mesh: quad.obj, material: material.yaml}\n");
    Options o = small((dir / "scene.yaml").string());
    o.editor = false;  // the picture alone, as shown
    Viewer v(o);
    key(SDLK_o);  // and no overlay over it
    v.pump();
    const size_t centre = (45 * 160 + 80) * 4;
    const uint8_t good = v.shown().at(centre);  // red 0.5, sRGB-encoded
    REQUIRE(good == linear_to_srgb8(0.5f));
    // A gain over 5 makes the shader loop: the frame is given up.
    write(dir / "material.yaml", "shader: stall\nparams: {gain: 6.0}\n");
    REQUIRE(pump_until(v, [&] {
        return has_message(v, "shader 'stall' (", true) &&
               has_message(v, "did not return from its fragment function within 1 s; the frame "
                              "was abandoned; frames wait for a change", true);
    }, 20s));
    const uint64_t frames = v.frames_rendered();
    for (int i = 0; i < 5; ++i) v.pump();
    CHECK(v.shown().at(centre) == good);  // the last good frame
    CHECK(v.frames_rendered() == frames);  // nothing drawn while it stalls
    // A change to the material draws again.
    write(dir / "material.yaml", "shader: stall\nparams: {gain: 0.75}\n");
    REQUIRE(pump_until(v, [&] { return v.shown().at(centre) == linear_to_srgb8(0.75f); }));
}

TEST_CASE("a scripted run's screenshot matches facet-render's image of the same view",
          "[viewer][script]") {
    const test::TempDir folder("view-script");
    const fs::path& dir = folder.path;
    const std::string camera = "--camera -1.5,0.9,-2.4,0,0.3,0.2,40 --size 320x180 --msaa 4";
    const std::string view = std::string(FACET_VIEW_EXE) + " --frames 2 " + camera +
                             " --screenshot " + (dir / "view.png").string() + " 2>/dev/null";
    const std::string render = std::string(FACET_RENDER_EXE) + " " + camera + " -o " +
                               (dir / "render.png").string() + " 2>/dev/null";
    REQUIRE(std::system(view.c_str()) == 0);
    REQUIRE(std::system(render.c_str()) == 0);
    int w1, h1, w2, h2, n;
    stbi_uc* a = stbi_load((dir / "view.png").c_str(), &w1, &h1, &n, 4);
    stbi_uc* b = stbi_load((dir / "render.png").c_str(), &w2, &h2, &n, 4);
    REQUIRE(a);
    REQUIRE(b);
    REQUIRE(w1 == 320);
    REQUIRE(h1 == 180);
    REQUIRE(w2 == w1);
    REQUIRE(h2 == h1);
    // Tolerance: one 8-bit code per channel (the same core renders both).
    int max_diff = 0, lit = 0;
    for (int i = 0; i < w1 * h1 * 4; ++i) max_diff = std::max(max_diff, std::abs(a[i] - b[i]));
    for (int i = 0; i < w1 * h1; ++i) lit += a[4 * i] > 100;
    stbi_image_free(a);
    stbi_image_free(b);
    INFO("max difference " << max_diff << " codes");
    CHECK(max_diff <= 1);
    CHECK(lit > 2000);  // the cow is in view
}

TEST_CASE("messages fade on time, and an idle viewer then sleeps", "[viewer]") {
    Options o = small();
    o.message_time = 150ms;
    Viewer v(o);
    v.pump();
    key(SDLK_p);  // a screenshot: "saved ..."
    v.pump();
    REQUIRE(v.messages().size() == 1);
    const int wait = v.wait_ms();
    CHECK(wait > 0);
    CHECK(wait <= 151);
    const uint64_t presents = v.frames_presented();
    std::this_thread::sleep_for(200ms);
    v.pump();
    CHECK(v.frames_presented() == presents + 1);  // the overlay without the message
    CHECK(v.messages().empty());
    CHECK(v.wait_ms() == -1);
}

TEST_CASE("fly keys never stick: both shifts, and a reset while a key is held", "[viewer]") {
    Viewer v(small());
    v.pump();
    key(SDLK_f);
    v.pump();
    auto press = [](SDL_Keycode k, bool down) {
        SDL_Event e{};
        e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
        e.key.keysym.sym = k;
        push(e);
    };
    press(SDLK_LSHIFT, true);
    press(SDLK_RSHIFT, true);
    v.pump();
    CHECK(v.wait_ms() == 1);  // moving
    press(SDLK_LSHIFT, false);
    press(SDLK_RSHIFT, false);
    v.pump();
    CHECK(v.wait_ms() == -1);
    press(SDLK_w, true);
    key(SDLK_r);
    press(SDLK_w, false);
    v.pump();
    CHECK(v.wait_ms() == -1);
    const glm::vec3 still = v.controller().camera().position;
    std::this_thread::sleep_for(20ms);
    v.pump();
    CHECK(v.controller().camera().position == still);
}

TEST_CASE("a scene edit keeps the user's camera unless the file's camera changed",
          "[viewer][reload]") {
    const test::TempDir folder("view-camera");
    const fs::path& dir = folder.path;
    write(dir / "quad.obj", test::kQuadObj);
    const std::string objects =
        "objects:\n  - {name: a, mesh: quad.obj, material: {shader: unlit}}\n"
        "  - {name: b, mesh: quad.obj, position: [0, 0, -1], material: {shader: unlit}}\n";
    write(dir / "scene.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n" + objects);
    Viewer v(small((dir / "scene.yaml").string()));
    v.pump();
    drag(30, 0, SDL_BUTTON_LMASK);
    key(SDLK_TAB);  // select the second object
    v.pump();
    REQUIRE(v.selected() == 1);
    const Camera orbited = v.controller().camera();
    // A light added, and one object fewer: the camera stays, the selection
    // stays valid.
    write(dir / "scene.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
                              "lights: [{type: directional, direction: [0, -1, 0]}]\n"
                              "objects:\n  - {name: a, mesh: quad.obj, material: {shader: unlit}}\n");
    REQUIRE(pump_until(v, [&] { return v.scene().lights.size() == 1; }));
    CHECK(v.controller().camera().position == orbited.position);
    CHECK(v.selected() == 0);
    key(SDLK_m);
    v.pump();
    CHECK(v.scene().objects[0].material->source.find("configs/materials") != std::string::npos);
    // The file's camera moved: the view follows it.
    write(dir / "scene.yaml", "camera: {position: [0, 1, 5], target: [0, 0, 0]}\n" + objects);
    REQUIRE(pump_until(v, [&] { return v.scene().objects.size() == 2; }));
    CHECK(v.controller().camera().position == glm::vec3(0, 1, 5));
}

TEST_CASE("odd input: a dropped non-scene file, a scene with no objects", "[viewer][bad]") {
    const test::TempDir folder("view-empty");
    const fs::path& dir = folder.path;
    write(dir / "empty.yaml", "camera: {position: [0, 0, 3], target: [0, 0, 0]}\nobjects: []\n");
    Viewer v(small((dir / "empty.yaml").string()));
    v.pump();
    REQUIRE(v.scene().objects.empty());
    key(SDLK_TAB);
    key(SDLK_m);
    v.pump();
    CHECK(has_message(v, "no object", true));
    SDL_Event drop{};
    drop.type = SDL_DROPFILE;
    drop.drop.file = SDL_strdup("/tmp/picture.png");
    push(drop);
    v.pump();
    CHECK(has_message(v, "not a scene file", true));
    CHECK(v.scene().source == dir / "empty.yaml");
}

namespace {

// A press and release of the left button at (x, y), a frame each, as a
// user's click spans frames.
void click(Viewer& v, float x, float y) {
    for (const Uint32 type : {SDL_MOUSEBUTTONDOWN, SDL_MOUSEBUTTONUP}) {
        SDL_Event e{};
        e.type = type;
        e.button.button = SDL_BUTTON_LEFT;
        e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
        e.button.clicks = 1;
        e.button.x = int(x);
        e.button.y = int(y);
        push(e);
        v.pump();
    }
}

// Types `text` into the field a double-click at (x, y) opens, then Enter.
void type_into(Viewer& v, const Editor::Rect& field, float dx, const std::string& text) {
    const float x = field.x + dx, y = field.y + field.h / 2;
    click(v, x, y);
    click(v, x, y);  // a double-click turns a drag field into a text field, all selected
    SDL_Event e{};
    e.type = SDL_TEXTINPUT;
    std::snprintf(e.text.text, sizeof e.text.text, "%s", text.c_str());
    push(e);
    v.pump();
    for (const bool down : {true, false}) {
        SDL_Event k{};
        k.type = down ? SDL_KEYDOWN : SDL_KEYUP;
        k.key.keysym.sym = SDLK_RETURN;
        k.key.keysym.scancode = SDL_SCANCODE_RETURN;
        push(k);
        v.pump();
    }
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST_CASE("the editor changes a material colour and a light by widget, and saves them in place",
          "[viewer][editor]") {
    const test::TempDir dir("view-editor");
    dir.write("quad.obj", test::kQuadObj);
    const fs::path material = dir.write("red.yaml",
                                        "# A lit red, edited by the test.\n"
                                        "shader: lit\n"
                                        "params:\n"
                                        "  base_color: [0.8, 0.1, 0.1, 1]  # red\n"
                                        "  ambient: [0.05, 0.05, 0.05]\n");
    const std::string scene_text =
        "# The editor's scene: every comment here must survive a save.\n"
        "camera: {position: [0, 0, 20], target: [0, 0, 0], fov_y: 50}\n"
        "lights:\n"
        "  - {type: directional, direction: [0, 0, -1], intensity: 1}  # the key\n"
        "objects:\n"
        "  - name: quad\n"
        "    mesh: quad.obj\n"
        "    material: red.yaml\n";
    const fs::path scene = dir.write("scene.yaml", scene_text);
    Options o = small(scene.string());
    o.size = glm::ivec2(900, 1000);  // the panel shows every widget the test uses
    o.materials = dir.path;
    Viewer v(o);
    REQUIRE(pump_until(v, [&] { return v.frames_presented() >= 1; }));
    REQUIRE(v.editor().visible());
    v.pump();

    // The material's base colour: its red component, through the colour widget.
    const auto colour = v.editor().widget("base_color");
    REQUIRE(colour);
    type_into(v, *colour, 6.0f, "0.25");
    REQUIRE(pump_until(v, [&] {
        const std::shared_ptr<Material>& m = v.scene().objects[0].material;
        for (const MaterialParam& p : m->params)
            if (p.name == "base_color") return p.numbers.at(0) == 0.25;
        return false;
    }, 3s));

    // The light's intensity, through its drag field (the Lights section opened first).
    const auto header = v.editor().widget("Lights");
    REQUIRE(header);
    click(v, header->x + 20, header->y + header->h / 2);
    v.pump();
    const auto intensity = v.editor().widget("intensity##light0");
    REQUIRE(intensity);
    type_into(v, *intensity, intensity->w / 4, "3");
    REQUIRE(pump_until(v, [&] { return v.scene().lights.at(0).intensity == 3.0f; }, 3s));
    CHECK(v.editor().unsaved() == 2);
    CHECK(read_text(scene) == scene_text);  // nothing written before Save
    // Closing the window with edits unsaved asks first.
    SDL_Event quit{};
    quit.type = SDL_QUIT;
    push(quit);
    CHECK(v.pump());
    CHECK(has_message(v, "2 unsaved values", true));

    // The picture with both changes, then Save, and the reload it causes.
    REQUIRE(pump_until(v, [&] { return !v.framebuffer().resolve_srgb8().empty(); }));
    v.pump();
    const std::vector<uint8_t> edited = v.framebuffer().resolve_srgb8();
    const uint64_t rendered = v.frames_rendered();
    const auto save = v.editor().widget("Save");
    REQUIRE(save);
    click(v, save->x + save->w / 2, save->y + save->h / 2);
    CHECK(v.editor().unsaved() == 0);
    CHECK(has_message(v, "saved", false));
    // Its own save is not reloaded: memory holds it already, and an edit
    // made just after it is not reverted.
    std::this_thread::sleep_for(300ms);
    for (int i = 0; i < 10; ++i) v.pump();
    CHECK_FALSE(has_message(v, "reloaded", false));
    CHECK(v.frames_rendered() == rendered);
    // Reloaded when the file changes on disk, it draws the same picture.
    { std::ofstream(scene, std::ios::app) << "# touched by hand\n"; }
    REQUIRE(pump_until(v, [&] { return has_message(v, "reloaded", false) && v.frames_rendered() > rendered; }));
    v.pump();
    CHECK(v.framebuffer().resolve_srgb8() == edited);  // the same picture from the files

    // The files kept their comments and order; only the values changed.
    const std::string saved_scene = read_text(scene);
    CHECK(saved_scene.find("# The editor's scene: every comment here must survive a save.\n") == 0);
    CHECK(saved_scene.find("intensity: 3}  # the key\n") != std::string::npos);
    const std::string saved_material = read_text(material);
    CHECK(saved_material.find("  base_color: [0.25, 0.1, 0.1, 1]  # red\n") != std::string::npos);
    CHECK(saved_material.find("# A lit red, edited by the test.\nshader: lit\n") == 0);
    // And a fresh load reads the values the editor set.
    PluginRegistry registry;
    const Scene fresh = load_scene(scene, registry);
    CHECK(fresh.lights.at(0).intensity == 3.0f);
    // An edit not saved when its file changes on disk is dropped, and said.
    const auto again = v.editor().widget("intensity##light0");
    REQUIRE(again);
    type_into(v, *again, again->w / 4, "5");
    REQUIRE(pump_until(v, [&] { return v.editor().unsaved() == 1; }, 3s));
    { std::ofstream(scene, std::ios::app) << "# touched again\n"; }
    REQUIRE(pump_until(v, [&] { return has_message(v, "1 unsaved values dropped", true); }));
    CHECK(v.editor().unsaved() == 0);
    CHECK(v.scene().lights.at(0).intensity == 3.0f);  // the file's
    // Nothing is unsaved now: closing the window quits.
    push(quit);
    CHECK_FALSE(v.pump());
}

TEST_CASE("the editor edits a part's material file, and shows a mesh file's own without changing it",
          "[viewer][editor]") {
    const test::TempDir dir("view-parts");
    const fs::path crate = fs::path(FACET_SOURCE_DIR) / "assets" / "crate_obj" / "crate.obj";
    dir.write("red.yaml", "shader: lit\nparams:\n  base_color: [0.8, 0.1, 0.1, 1]\n");
    auto scene_with = [&](const std::string& materials) {
        return dir.write("scene.yaml",
                         "camera: {position: [2, 2, 3], target: [0, 0.5, 0], fov_y: 40}\n"
                         "lights: [{type: directional, direction: [-1, -1, -1], intensity: 1}]\n"
                         "objects:\n  - name: crate\n    mesh: " + crate.string() + "\n" +
                             materials);
    };
    {
        // The crate's sides (its first part, 'wood') take red.yaml: the panel
        // shows that first, and an edit goes into the file.
        Options o = small(scene_with("    materials: {wood: red.yaml}\n").string());
        o.size = glm::ivec2(900, 1000);
        Viewer v(o);
        REQUIRE(pump_until(v, [&] { return v.frames_presented() >= 1; }));
        v.pump();
        REQUIRE(v.editor().widget("part material"));  // the crate has several
        const auto colour = v.editor().widget("base_color");
        REQUIRE(colour);
        type_into(v, *colour, 6.0f, "0.25");
        REQUIRE(pump_until(v, [&] { return v.editor().unsaved() == 1; }, 3s));
        const Material& red = *v.scene().objects[0].material_of(0);
        CHECK(red.params.at(0).numbers.at(0) == 0.25);
    }
    {
        // Without it the sides draw with the .mtl's material: shown, not changed.
        Options o = small(scene_with("").string());
        o.size = glm::ivec2(900, 1000);
        Viewer v(o);
        REQUIRE(pump_until(v, [&] { return v.frames_presented() >= 1; }));
        v.pump();
        const auto diffuse = v.editor().widget("diffuse");
        REQUIRE(diffuse);
        type_into(v, *diffuse, 6.0f, "0.25");
        for (int i = 0; i < 10; ++i) v.pump();
        CHECK(v.editor().unsaved() == 0);
        const Material& wood = *v.scene().objects[0].material_of(0);
        CHECK(wood.source.find("crate.obj: material 'wood'") != std::string::npos);
        for (const MaterialParam& p : wood.params)
            if (p.name == "diffuse") CHECK(p.numbers.at(0) == 1.0);  // Kd 1 1 1, unchanged
    }
}

TEST_CASE("the editor's selection is outlined in the shown image only, and E hides the panel",
          "[viewer][editor]") {
    Options o = small((fs::path(FACET_SOURCE_DIR) / "configs/scenes/phong.yaml").string());
    o.size = glm::ivec2(320, 180);
    Viewer v(o);
    v.pump();
    key(SDLK_o);  // no stats overlay: what differs is the outline
    v.pump();
    const std::vector<uint8_t> frame = v.framebuffer().resolve_srgb8();
    std::vector<uint8_t> shown = v.shown();
    REQUIRE(shown.size() == frame.size());
    size_t orange = 0, other = 0;
    for (size_t i = 0; i < frame.size(); i += 4) {
        if (std::equal(&frame[i], &frame[i] + 4, &shown[i])) continue;
        (shown[i] == 255 && shown[i + 1] == 160 && shown[i + 2] == 30 ? orange : other) += 1;
    }
    CHECK(orange > 50);
    CHECK(other == 0);
    // Tab selects the next object: the outline moves.
    key(SDLK_TAB);
    v.pump();
    CHECK(v.selected() == 1);
    CHECK(v.shown() != shown);
    // A screenshot has no outline.
    const test::TempDir dir("view-outline");
    v.save_screenshot(dir.path / "shot.png");
    int w = 0, h = 0, n = 0;
    stbi_uc* pixels = stbi_load((dir.path / "shot.png").c_str(), &w, &h, &n, 4);
    REQUIRE(pixels);
    CHECK(std::equal(pixels, pixels + size_t(w) * h * 4, v.framebuffer().resolve_srgb8().begin()));
    stbi_image_free(pixels);
    key(SDLK_e);
    v.pump();
    CHECK_FALSE(v.editor().visible());
    CHECK(v.shown() == v.framebuffer().resolve_srgb8());
}

TEST_CASE("the editor's Euler angles make the rotation they were read from, at gimbal lock too",
          "[editor]") {
    int checked = 0;
    for (float pitch : {-90.0f, -89.999f, -45.0f, 0.0f, 30.0f, 89.9995f, 90.0f})
        for (float yaw : {-170.0f, -90.0f, 0.0f, 20.0f, 90.0f, 135.0f})
            for (float roll : {-120.0f, 0.0f, 20.0f, 90.0f}) {
                const glm::quat q = euler_degrees({yaw, pitch, roll});
                const glm::vec3 e = to_euler_degrees(q);
                INFO(yaw << " " << pitch << " " << roll << " -> " << e.x << " " << e.y << " " << e.z);
                CHECK(std::abs(glm::dot(euler_degrees(e), q)) > 1.0f - 1e-6f);
                ++checked;
            }
    CHECK(checked == 168);
}

TEST_CASE("the viewer plays, pauses, steps and scrubs a scene's animation", "[viewer][animation]") {
    Viewer v(small(std::string(FACET_SOURCE_DIR) + "/configs/scenes/turntable.yaml"));
    v.pump();
    REQUIRE(v.scene().animated());
    CHECK(v.playback().time() == 0.0);
    CHECK_FALSE(v.playback().playing());
    CHECK(v.following_camera());  // the scene's camera is animated
    CHECK(stats_text(v.overlay()).find("frame 0  24 fps  paused") != std::string::npos);
    const std::vector<uint8_t> first = v.shown();

    key(SDLK_SPACE);  // play
    const uint64_t rendered = v.frames_rendered();
    REQUIRE(pump_until(v, [&] { return v.playback().time() > 0.2; }));
    CHECK(v.playback().playing());
    CHECK(v.frames_rendered() > rendered + 1);  // a frame each pump while it plays
    CHECK(v.wait_ms() == 0);
    CHECK(v.shown() != first);
    // The scene is posed at the playback's time, the view on its camera.
    CHECK(v.scene().time == v.playback().time());
    Scene posed = v.scene();
    posed.pose(v.playback().time());
    CHECK(v.controller().camera().position == posed.camera.position);

    key(SDLK_SPACE);  // pause
    v.pump();
    const double paused = v.playback().time();
    const uint64_t after_pause = v.frames_rendered();
    for (int i = 0; i < 5; ++i) v.pump();
    CHECK(v.playback().time() == paused);
    CHECK(v.frames_rendered() == after_pause);

    key(SDLK_HOME);
    key(SDLK_RIGHT);
    key(SDLK_RIGHT);
    v.pump();
    CHECK(v.playback().time() == Approx(2.0 / 24.0));
    CHECK(v.scene().time == v.playback().time());
    key(SDLK_LEFT);
    key(SDLK_LEFT);
    key(SDLK_LEFT);  // before the start: wraps to the last frame
    v.pump();
    CHECK(v.playback().time() == Approx(191.0 / 24.0));

    v.seek(2.0);  // what the editor's time slider does
    v.pump();
    CHECK(v.scene().time == 2.0);
    REQUIRE(v.editor().widget("time"));
    // Moving the camera by hand stops it following; R follows again.
    drag(30, 0, SDL_BUTTON_LMASK);
    v.pump();
    CHECK_FALSE(v.following_camera());
    CHECK(stats_text(v.overlay()).find("camera free") != std::string::npos);
    key(SDLK_r);
    v.pump();
    CHECK(v.following_camera());
}

TEST_CASE("Space on a scene that does not move says so", "[viewer][animation]") {
    Viewer v(small());
    v.pump();
    key(SDLK_SPACE);
    v.pump();
    CHECK_FALSE(v.playback().playing());
    CHECK(has_message(v, "does not move", true));
}

TEST_CASE("the editor moves a still object and an animated one's place at rest",
          "[viewer][editor][animation]") {
    Options o = small(std::string(FACET_SOURCE_DIR) + "/configs/scenes/turntable.yaml");
    o.size = glm::ivec2(900, 1000);  // the panel shows the object's fields
    for (const char* name : {"ground", "spot"}) {  // still, and turning
        INFO(name);
        o.select = name;
        Viewer v(o);
        REQUIRE(pump_until(v, [&] { return v.frames_presented() >= 1; }));
        v.pump();
        const Object& object = v.scene().objects[size_t(v.selected())];
        REQUIRE(object.name == name);
        const auto position = v.editor().widget("position");
        REQUIRE(position);
        type_into(v, *position, 6.0f, "0.5");
        REQUIRE(pump_until(v, [&] { return object.rest.translation.x == 0.5f; }, 3s));
        CHECK(object.transform.translation.x == 0.5f);  // drawn there
        v.seek(2.0);  // a spin turns Spot; its edited place at rest stays
        v.pump();
        CHECK(object.transform.translation.x == 0.5f);
        CHECK((object.transform.rotation != object.rest.rotation) == !object.animation.empty());
    }
}

TEST_CASE("the editor writes a texture back with everything it sets", "[viewer][editor]") {
    MaterialParam p;
    p.kind = MaterialParam::Kind::texture;
    p.texture_file = "/materials/textures/tiles.png";
    const auto parsed = [&] { return YAML::Load(view::texture_yaml(p, "/materials")); };
    YAML::Node n = parsed();
    CHECK(n["file"].as<std::string>() == "textures/tiles.png");
    CHECK(n["filter"].as<std::string>() == "trilinear");
    CHECK(n["wrap"].as<std::string>() == "repeat");
    CHECK(n.size() == 3);  // nothing that is as the defaults have it
    p.filter = Filter::anisotropic;
    p.anisotropy = 8;
    p.wrap = Wrap::mirror;
    p.uv_set = 1;
    p.transform.offset = {0.5f, -1.0f};
    p.transform.rotation = 0.1f;
    p.transform.scale = {2.0f, 1.0f / 3.0f};
    n = parsed();
    CHECK(n["filter"].as<std::string>() == "anisotropic");
    CHECK(n["anisotropy"].as<int>() == 8);
    CHECK(n["wrap"].as<std::string>() == "mirror");
    CHECK(n["uv_set"].as<int>() == 1);
    CHECK(n["transform"]["offset"][1].as<float>() == -1.0f);
    CHECK(n["transform"]["rotation"].as<float>() == 0.1f);  // every float as it was
    CHECK(n["transform"]["scale"][1].as<float>() == 1.0f / 3.0f);
    p = MaterialParam{};
    p.kind = MaterialParam::Kind::texture;
    for (const char* face : {"px", "nx", "py", "ny", "pz", "nz"})
        p.cube_faces.push_back(std::string("/materials/sky/") + face + ".png");
    n = parsed();
    CHECK_FALSE(n["file"]);
    REQUIRE(n["faces"].size() == 6);
    CHECK(n["faces"][5].as<std::string>() == "sky/nz.png");
}
