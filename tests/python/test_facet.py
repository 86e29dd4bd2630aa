"""The Python module `facet` (python/facet_module.cpp), with pytest: run by
the test command (tests/CMakeLists.txt: python), with the module's folder
on PYTHONPATH and FACET_RENDER naming facet-render."""
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import facet

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from png_pixels import pixels as png_pixels_of  # noqa: E402

SPHERE = """
camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 45}
render: {size: [40, 30], clear_color: [0.1, 0.2, 0.3, 1]}
lights:
  - {name: sun, type: directional, direction: [-1, -1, -1], color: [1, 1, 1], intensity: 2}
objects:
  - name: ball
    mesh: ../../assets/sphere/sphere.obj
    material: {shader: phong, params: {diffuse: [0.8, 0.3, 0.2]}}
"""


def origin():
    """A file beside the demo scenes, for YAML text to be read as."""
    return os.path.join(os.path.dirname(facet.default_scene()), "scenes", "api.yaml")


def png_pixels(path):
    """A PNG's 8-bit RGBA pixels as an (H, W, 4) array (tests/png_pixels.py)."""
    (w, h), rows = png_pixels_of(path)
    return np.frombuffer(b"".join(rows), np.uint8).reshape(h, w, 4)


def test_render_is_facet_renders_pixels(tmp_path):
    image = facet.render(facet.default_scene(), size=(64, 48), threads=2)
    assert image.shape == (48, 64, 4) and image.dtype == np.uint8
    out = tmp_path / "cli.png"
    subprocess.run([os.environ["FACET_RENDER"], "--size", "64x48", "-q", "-o", str(out)],
                   check=True)
    assert np.array_equal(image, png_pixels(out))


def test_a_scene_changes_and_renders():
    scene = facet.Scene.from_yaml(SPHERE, origin())
    assert scene.size == (40, 30) and scene.light_count == 1
    lit = scene.render()
    assert lit.shape == (30, 40, 4)
    hdr = scene.render_float()
    assert hdr.dtype == np.float32 and hdr.shape == (30, 40, 4)
    assert hdr[0, 0, 0] == pytest.approx(0.1) and hdr[0, 0, 3] == 1.0  # the clear colour
    # Each setter: an image unlike the one before.
    scene.set_param("ball", "diffuse", [0, 0, 0])
    dark = scene.render()
    assert dark.astype(int).sum() < lit.astype(int).sum()
    scene.set_param("ball", "shininess", 2)
    broad = scene.render()
    assert not np.array_equal(broad, dark)
    scene.set_light(0, [1, 0, 0], 0.5)
    red = scene.render()
    assert not np.array_equal(red, broad)
    scene.set_light("sun", [0, 0, 1], 0.5)
    assert not np.array_equal(scene.render(), red)
    scene.set_camera([0, 1, 4], [0, 0, 0], 30)
    assert not np.array_equal(scene.render(), red)
    scene.set_time(0.5)
    scene.size = (20, 10)
    assert scene.render().shape == (10, 20, 4)


def test_errors_name_what_is_wrong():
    with pytest.raises(facet.Error) as e:
        facet.render("no-such-scene.yaml")
    assert e.value.file == "no-such-scene.yaml" and "not found" in str(e.value)
    with pytest.raises(facet.Error) as e:
        facet.Scene.from_yaml("objects: [", origin())
    assert e.value.line > 0 and e.value.file.endswith("api.yaml")
    scene = facet.Scene.from_yaml(SPHERE, origin())
    with pytest.raises(facet.Error, match="no_such"):
        scene.set_param("ball", "no_such", 1)
    with pytest.raises(facet.Error, match="takes 3"):
        scene.set_param("ball", "diffuse", [1, 2])
    with pytest.raises(facet.Error, match="texture"):
        scene.set_param("ball", "base_texture", 1)
    with pytest.raises(facet.Error, match="no light named 'moon'"):
        scene.set_light("moon", [1, 1, 1], 1)
    with pytest.raises(facet.Error, match="nobody"):
        scene.set_param("nobody", "diffuse", [1, 1, 1])
    with pytest.raises(facet.Error):
        scene.set_time(float("nan"))
    with pytest.raises(facet.Error):
        scene.size = (0, 5)
    assert isinstance(e.value, RuntimeError)


def test_a_scene_is_one_threads_while_it_renders():
    scene = facet.Scene(facet.default_scene())
    scene.size = (3840, 2160)
    scene.render(threads=1)
    started = threading.Event()
    worker = threading.Thread(target=lambda: (started.set(), scene.render(threads=1)))
    worker.start()
    started.wait()
    time.sleep(0.02)
    refused = False
    if worker.is_alive():  # it still renders: a change now is refused, not a race
        with pytest.raises(facet.Error, match="another thread"):
            scene.size = (10, 5000)
        refused = True
    worker.join()
    assert refused
    scene.size = (16, 9)
    assert scene.render().shape == (9, 16, 4)


def srgb8(linear):
    """Linear RGB in 0..1 as sRGB-encoded 8-bit codes."""
    x = np.clip(linear, 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.floor(s * 255 + 0.5).astype(int)


def test_float_pixels_are_linear_before_the_post_chain():
    # No post chain: the floats, encoded, are the 8-bit image (within a code).
    plain = facet.Scene.from_yaml(SPHERE, origin())
    assert np.abs(srgb8(plain.render_float()[..., :3]) - plain.render()[..., :3]).max() <= 1
    # A post chain: the 8-bit image has it, the floats do not.
    post = facet.Scene(os.path.join(os.path.dirname(facet.default_scene()), "scenes", "post.yaml"))
    post.size = (64, 36)
    hdr = post.render_float()
    assert hdr.dtype == np.float32 and hdr.shape == (36, 64, 4) and np.isfinite(hdr).all()
    assert np.abs(srgb8(hdr[..., :3]) - post.render()[..., :3]).max() > 8


def test_the_gil_is_released_while_rendering():
    scene = facet.Scene(facet.default_scene())
    scene.size = (3840, 2160)
    scene.render(threads=1)  # warm: plugins and buffers
    started = threading.Event()

    def work():
        started.set()
        scene.render(threads=1)  # hundreds of milliseconds

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    time.sleep(0.02)
    # The main thread runs Python here while the frame renders only if the
    # render let the GIL go; held, it waits for the whole frame.
    assert worker.is_alive()
    worker.join()
