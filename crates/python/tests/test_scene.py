"""Loading scenes (every format the command reads, dicts, built-ins) and editing them."""

import math

import numpy as np
import pytest

import irradia

SPHERE = {
    "image": {"width": 32, "height": 24},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 40},
    "lights": [{"type": "point", "position": [5, 5, 5], "intensity": [1, 1, 1]}],
    "materials": {"red": {"color": [0.8, 0.1, 0.1]}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red"}],
}


def test_builtins_listed_and_loaded():
    names = dict(irradia.builtins())
    assert "cornell" in names and "whitted" in names
    s = irradia.builtin("cornell")
    assert s.integrator == "path"
    assert s.source == "builtin:cornell.toml"
    assert "cornell" in repr(s)


@pytest.mark.parametrize(
    "rel",
    [
        "mitsuba/box.xml",
        "pbrt/cornell.pbrt",
        "pbrt/cornell.toml",
        "obj/scene.obj",
        "ply/quad_le.ply",
        "gltf/camera_lights.gltf",
        "gltf/textured_box.glb",
    ],
)
def test_load_every_format(data, rel):
    s = irradia.load(data / rel)
    assert s.width > 0 and s.height > 0
    assert len(s.objects) > 0
    img = s.render(width=16, height=12, spp=1, threads=1)
    assert img.shape == (12, 16, 3) and img.dtype == np.float32
    assert np.isfinite(img).all()


def test_load_json_file(tmp_path):
    import json

    p = tmp_path / "s.json"
    p.write_text(json.dumps(SPHERE))
    s = irradia.load(p)
    assert (s.width, s.height) == (32, 24)


def test_load_dict_equals_file(tmp_path, cli):
    import json

    p = tmp_path / "s.json"
    p.write_text(json.dumps(SPHERE))
    a = irradia.load_dict(SPHERE).render()
    b = irradia.load(p).render()
    assert np.array_equal(a, b)


def test_load_dict_error_names_field():
    bad = dict(SPHERE, objects=[{"type": "sphere", "center": [0, 0, 0], "radius": -1, "material": "red"}])
    with pytest.raises(irradia.IrradiaError, match=r"objects\[0\]\.radius"):
        irradia.load_dict(bad)
    with pytest.raises(irradia.IrradiaError):
        irradia.load_dict({"objects": [{"type": "sphere", "radius": float("nan")}]})
    with pytest.raises(irradia.IrradiaError):
        irradia.load_dict([1, 2])


def test_properties_and_settings():
    s = irradia.load_dict(SPHERE)
    s.width, s.height, s.spp, s.max_depth = 40, 30, 2, 3
    assert (s.width, s.height, s.spp, s.max_depth) == (40, 30, 2, 3)
    assert s.render().shape == (30, 40, 3)
    s.integrator = "path"
    assert s.integrator == "path"
    with pytest.raises(irradia.IrradiaError, match="unknown integrator"):
        s.integrator = "bidir"
    with pytest.raises(irradia.IrradiaError):
        s.width = 0
    assert s.width == 40  # a refused value changes nothing


def test_camera_edit_changes_image():
    s = irradia.load_dict(SPHERE)
    before = s.render()
    cam = s.camera
    assert cam["projection"] == "perspective" and math.isclose(cam["fov"], 40)
    s.set_camera(eye=[0, 0, 8], fov=30)
    assert s.camera["eye"] == [0, 0, 8]
    assert not np.array_equal(before, s.render())
    with pytest.raises(irradia.IrradiaError, match="eye and look_at must differ"):
        s.set_camera(eye=[0, 0, 0])
    with pytest.raises(irradia.IrradiaError, match="camera.fov"):
        s.set_camera(fov=200)
    with pytest.raises(irradia.IrradiaError, match="camera.eye"):
        s.set_camera(eye=[1, 2])


def test_material_edit():
    s = irradia.load_dict(SPHERE)
    centre = s.render()[12, 16]
    s.set_material("red", color=(0.1, 0.8, 0.1))
    assert s.materials[0]["color"] == pytest.approx([0.1, 0.8, 0.1])
    green = s.render()[12, 16]
    assert green[1] > green[0] and centre[0] > centre[1]
    s.set_material(0, diffuse=0.0, ambient=0.0, specular=0.0)
    assert s.render()[12, 16].max() == 0.0
    with pytest.raises(KeyError, match="unknown material 'blue'"):
        s.set_material("blue", diffuse=1)
    with pytest.raises(irradia.IrradiaError, match="unknown material field"):
        s.set_material("red", glow=1)
    with pytest.raises(irradia.IrradiaError, match="not negative"):
        s.set_material("red", diffuse=-1)


def test_light_edit():
    s = irradia.load_dict(SPHERE)
    assert s.lights[0]["type"] == "point"
    bright = s.render().sum()
    s.set_light(0, intensity=(0.5, 0.5, 0.5))
    assert s.lights[0]["intensity"] == [0.5, 0.5, 0.5]
    assert s.render().sum() < bright
    with pytest.raises(IndexError):
        s.set_light(3, intensity=1)
    with pytest.raises(irradia.IrradiaError, match="has no editable field 'radius'"):
        s.set_light(0, radius=2)


def test_bad_files_raise_with_cli_message(tmp_path, cli):
    bad = tmp_path / "bad.toml"
    bad.write_text('[camera]\neye = [0, 0, 5]\n\n[[objects]]\ntype = "sphere"\nradius = -2\n')
    with pytest.raises(irradia.IrradiaError) as e:
        irradia.load(bad)
    r = cli("render", bad, "-o", tmp_path / "x.png", "--quiet", check=False)
    assert r.returncode == 2
    assert str(e.value) in r.stderr
    assert "bad.toml:" in str(e.value)

    missing = tmp_path / "missing.toml"
    with pytest.raises(irradia.IrradiaError) as e:
        irradia.load(missing)
    r = cli("render", missing, "-o", tmp_path / "x.png", check=False)
    assert r.returncode == 2 and str(e.value) in r.stderr

    with pytest.raises(irradia.IrradiaError) as e:
        irradia.builtin("nope")
    r = cli("render", "--builtin", "nope", check=False)
    assert r.returncode == 2 and str(e.value) in r.stderr

    with pytest.raises(irradia.IrradiaError, match="is a directory"):
        irradia.load(tmp_path)
    garbage = tmp_path / "g.gltf"
    garbage.write_bytes(b"\x00\x01not json")
    with pytest.raises((irradia.IrradiaError, OSError)):
        irradia.load(garbage)
