// The Python module `facet`: facet's core from Python, images as numpy
// arrays (docs/embedding/python.md).
//
//     import facet
//     image = facet.render("scene.yaml")          # uint8, (H, W, 4)
//     scene = facet.Scene("scene.yaml")
//     scene.set_param("ball", "diffuse", [1, 0, 0])
//     hdr = scene.render_float()                    # float32, (H, W, 4), linear
//
// Errors are facet.Error (a RuntimeError) with .file and .line. The GIL is
// released while a frame renders.
#include <facet/error.hpp>
#include <facet/facet.h>
#include <facet/paths.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <dlfcn.h>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

// facet.Error, made at import and kept for the process (a handle: no
// reference is dropped after the interpreter has gone).
py::handle error_type;

// Raises facet.Error with `message`, and the C API's file and line.
[[noreturn]] void raise_error(const std::string& message, const std::string& file, int line) {
    py::object e = py::reinterpret_borrow<py::object>(error_type)(message);
    e.attr("file") = file;
    e.attr("line") = line;
    PyErr_SetObject(error_type.ptr(), e.ptr());
    throw py::error_already_set();
}

// Raises facet.Error from the C API's last error.
[[noreturn]] void raise_last_error() {
    raise_error(facet_error_message(), facet_error_file(), facet_error_line());
}

void check(facet_status s) {
    if (s != FACET_OK) raise_last_error();
}

// Where facet is: this module's folder's parent in a build tree
// (build/python), or the prefix of P/lib/python3/dist-packages.
fs::path install_root() {
    Dl_info info{};
    dladdr(reinterpret_cast<void*>(&install_root), &info);
    const fs::path dir = fs::path(info.dli_fname ? info.dli_fname : ".").parent_path();
    const std::string name = dir.filename().string();
    if (name == "dist-packages" || name == "site-packages")
        return dir.parent_path().parent_path().parent_path();
    return dir.parent_path();
}

struct SceneDeleter {
    void operator()(facet_scene* s) const { facet_scene_free(s); }
};
struct RendererDeleter {
    void operator()(facet_renderer* r) const { facet_renderer_free(r); }
};

std::array<float, 3> three(const std::vector<float>& v, const char* what) {
    if (v.size() != 3) throw py::value_error(std::string(what) + " takes 3 numbers");
    return {v[0], v[1], v[2]};
}

// A scene and the renderer that draws it.
class Scene {
public:
    explicit Scene(facet_scene* s) : scene_(s) {
        if (!scene_) raise_last_error();
    }
    static Scene load(const std::string& path) { return Scene(facet_scene_load(path.c_str())); }
    static Scene from_yaml(const std::string& yaml, std::optional<std::string> origin) {
        return Scene(facet_scene_load_yaml(yaml.c_str(), origin ? origin->c_str() : nullptr));
    }

    std::pair<int, int> size() const {
        idle();
        int w = 0, h = 0;
        check(facet_scene_size(scene_.get(), &w, &h));
        return {w, h};
    }
    void set_size(std::pair<int, int> wh) {
        idle();
        check(facet_scene_set_size(scene_.get(), wh.first, wh.second));
    }
    void set_camera(const std::vector<float>& position, const std::vector<float>& target,
                    float fov_y) {
        idle();
        const auto p = three(position, "position"), t = three(target, "target");
        check(facet_scene_set_camera(scene_.get(), p.data(), t.data(), fov_y));
    }
    void set_param(const std::string& object, const std::string& param, py::object value) {
        idle();
        std::vector<float> v;
        if (py::isinstance<py::bool_>(value) || py::isinstance<py::int_>(value) ||
            py::isinstance<py::float_>(value))
            v.push_back(value.cast<float>());
        else
            v = value.cast<std::vector<float>>();
        check(facet_scene_set_param(scene_.get(), object.c_str(), param.c_str(), v.data(),
                                    int(v.size())));
    }
    int light_count() const {
        idle();
        return facet_scene_light_count(scene_.get());
    }
    void set_light(py::object light, const std::vector<float>& color, float intensity) {
        idle();
        const auto c = three(color, "color");
        int index;
        if (py::isinstance<py::str>(light)) {
            index = facet_scene_light_index(scene_.get(), light.cast<std::string>().c_str());
            if (index < 0) raise_last_error();
        } else {
            index = light.cast<int>();
        }
        check(facet_scene_set_light(scene_.get(), index, c.data(), intensity));
    }
    void set_time(double seconds) {
        idle();
        check(facet_scene_set_time(scene_.get(), seconds));
    }

    py::array_t<uint8_t> render(int threads) { return rendered<uint8_t>(threads, 4); }
    py::array_t<float> render_float(int threads) { return rendered<float>(threads, 4); }

private:
    // Raises facet.Error while another thread renders the scene (the GIL is
    // let go then, and a handle is one thread's at a time).
    void idle() const {
        if (busy_) raise_error("the scene is being rendered by another thread", "", 0);
    }

    template <class T>
    py::array_t<T> rendered(int threads, int channels) {
        facet_renderer* r = renderer(threads);  // checks idle()
        const auto [w, h] = size();
        py::array_t<T> out({h, w, channels});
        T* pixels = out.mutable_data();
        const size_t stride = size_t(w) * size_t(channels) * sizeof(T);
        facet_status s;
        {
            busy_ = true;  // set and cleared while the GIL is held
            py::gil_scoped_release unlocked;
            if constexpr (std::is_same_v<T, uint8_t>)
                s = facet_render_rgba8(r, scene_.get(), pixels, stride);
            else
                s = facet_render_rgba32f(r, scene_.get(), pixels, stride);
        }
        busy_ = false;
        check(s);
        return out;
    }
    facet_renderer* renderer(int threads) {
        idle();
        if (!renderer_ || threads != threads_) {
            renderer_.reset(facet_renderer_new(threads));
            if (!renderer_) raise_last_error();
            threads_ = threads;
        }
        return renderer_.get();
    }

    std::unique_ptr<facet_scene, SceneDeleter> scene_;
    std::unique_ptr<facet_renderer, RendererDeleter> renderer_;
    int threads_ = 0;
    bool busy_ = false;
};

py::array_t<uint8_t> render(const std::string& path, std::optional<std::pair<int, int>> size,
                            int threads) {
    Scene scene = Scene::load(path);
    if (size) scene.set_size(*size);
    return scene.render(threads);
}

}  // namespace

PYBIND11_MODULE(facet, m) {
    m.doc() = "facet, a CPU rasterizer whose shaders are plugins: scenes rendered to numpy arrays";
    error_type = PyErr_NewExceptionWithDoc(
        "facet.Error", "an error of facet's, with .file and .line", PyExc_RuntimeError, nullptr);
    if (!error_type) throw py::error_already_set();
    m.attr("Error") = error_type;
    check(facet_set_install_root(install_root().c_str()));
    facet_set_log_level("warn");
    m.attr("api_version") = facet_api_version();
    m.def("render", &render, py::arg("path"), py::arg("size") = py::none(), py::arg("threads") = 0,
          "The scene file's image: uint8, shape (H, W, 4), sRGB-encoded RGBA, as facet-render "
          "writes it. size=(W, H) overrides the scene's; threads=0: one a core.");
    m.def("default_scene", [] {
        const char* s = facet_default_scene();
        if (!s) raise_last_error();
        return std::string(s);
    }, "facet's default scene file");
    m.def(
        "set_log_level",
        [](const std::string& level) { check(facet_set_log_level(level.c_str())); },
        "trace, debug, info, warn (the module's default), error or off");
    py::class_<Scene>(m, "Scene", "a scene, to change and render")
        .def(py::init(&Scene::load), py::arg("path"))
        .def_static("from_yaml", &Scene::from_yaml, py::arg("yaml"), py::arg("origin") = py::none(),
                    "a scene from YAML text, read as if it were the file `origin` (whose folder "
                    "resolves the files it names)")
        .def_property("size", &Scene::size, &Scene::set_size, "(width, height)")
        .def("set_camera", &Scene::set_camera, py::arg("position"), py::arg("target"),
             py::arg("fov_y"))
        .def("set_param", &Scene::set_param, py::arg("object"), py::arg("param"), py::arg("value"),
             "sets a material parameter of the object named `object`: a number or 2 to 4")
        .def_property_readonly("light_count", &Scene::light_count)
        .def("set_light", &Scene::set_light, py::arg("light"), py::arg("color"),
             py::arg("intensity"), "light `light`: its index, or its name in the file")
        .def("set_time", &Scene::set_time, py::arg("seconds"))
        .def("render", &Scene::render, py::arg("threads") = 0,
             "uint8, shape (H, W, 4), sRGB-encoded RGBA")
        .def("render_float", &Scene::render_float, py::arg("threads") = 0,
             "float32, shape (H, W, 4), linear RGBA before the scene's post chain");
}
