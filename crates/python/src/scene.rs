//! `irradia.Scene`: a validated scene loaded from a file of any format the command line
//! reads, from a dict in the TOML schema, or a built-in by name; its camera, image
//! settings, materials and lights read and edited from Python; and its methods
//! `render`, `trace_pixel` and `cast_rays` (the work is in `render.rs`, `raycast.rs`).

use crate::convert::{json_to_py, non_negative, rgb, vec3};
use crate::errors;
use irradia_scene::{Camera, Integrator, Light, Material, Projection, Scene, Texture};
use numpy::PyReadonlyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A scene ready to render. Make one with `irradia.load`, `irradia.load_dict` or
/// `irradia.builtin`.
#[pyclass(name = "Scene", module = "irradia")]
pub struct PyScene {
    pub scene: Scene,
    /// The importer's warnings (features read but not rendered).
    pub warnings: Vec<String>,
    /// What the last render measured.
    pub last: Option<Py<PyDict>>,
}

impl PyScene {
    pub fn new(scene: Scene, warnings: Vec<String>) -> Self {
        Self {
            scene,
            warnings,
            last: None,
        }
    }
}

/// The integrator by the command line's name (`--integrator`).
pub fn integrator_by_name(name: &str) -> PyResult<Integrator> {
    match name {
        "whitted" => Ok(Integrator::Whitted),
        "path" => Ok(Integrator::Path),
        _ => Err(errors::input(format!(
            "integrator: unknown integrator '{name}' (use whitted or path)"
        ))),
    }
}

fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::Whitted => "whitted",
        Integrator::Path => "path",
        Integrator::Direct { .. } => "direct",
    }
}

/// Reads a scene file of any format `irradia render` reads (by its extension).
#[pyfunction]
#[pyo3(signature = (path, *, defines=None, strict=false))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    defines: Option<std::collections::BTreeMap<String, String>>,
    strict: bool,
) -> PyResult<PyScene> {
    let opts = irradia_import::Options {
        defines: defines.unwrap_or_default().into_iter().collect(),
        strict,
    };
    let (scene, imported) = py
        .allow_threads(|| {
            irradia_import::check_path(&path)?;
            irradia_import::load(&path, &opts)
        })
        .map_err(errors::scene)?;
    let warnings = imported.warnings.iter().map(|w| w.to_string()).collect();
    Ok(PyScene::new(scene, warnings))
}

/// A scene from JSON text in the scene-file schema (`irradia.load_dict` serialises a
/// dict to it); relative file names resolve against `base_dir`.
#[pyfunction]
#[pyo3(signature = (text, base_dir=None))]
pub fn _load_json(py: Python<'_>, text: &str, base_dir: Option<PathBuf>) -> PyResult<PyScene> {
    let origin = base_dir.unwrap_or_default().join("<dict>.json");
    let scene = py
        .allow_threads(|| irradia_scene::load_str(text, irradia_scene::SceneSyntax::Json, &origin))
        .map_err(errors::scene)?;
    Ok(PyScene::new(scene, Vec::new()))
}

/// A built-in scene by name (`irradia scenes` lists them; so does `irradia.builtins()`).
#[pyfunction]
pub fn builtin(py: Python<'_>, name: &str) -> PyResult<PyScene> {
    let scene = py
        .allow_threads(|| irradia_scene::builtin::load(name))
        .map_err(errors::scene)?;
    Ok(PyScene::new(scene, Vec::new()))
}

/// The built-in scenes: name -> one-line description.
#[pyfunction]
pub fn builtins() -> Vec<(&'static str, &'static str)> {
    irradia_scene::builtin::names()
}

fn camera_dict<'py>(py: Python<'py>, c: &Camera) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("eye", c.eye.to_array())?;
    d.set_item("look_at", c.look_at.to_array())?;
    d.set_item("up", c.up.to_array())?;
    match c.projection {
        Projection::Perspective { fov_degrees, .. } => {
            d.set_item("projection", "perspective")?;
            d.set_item("fov", fov_degrees)?;
        }
        Projection::ThinLens {
            fov_degrees,
            aperture_radius,
            focus_distance,
            ..
        } => {
            d.set_item("projection", "thinlens")?;
            d.set_item("fov", fov_degrees)?;
            d.set_item("aperture_radius", aperture_radius)?;
            d.set_item("focus_distance", focus_distance)?;
        }
        Projection::Orthographic { height } => {
            d.set_item("projection", "orthographic")?;
            d.set_item("height", height)?;
        }
    }
    Ok(d)
}

fn material_dict<'py>(py: Python<'py>, m: &Material) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &m.name)?;
    match &m.color {
        Texture::Solid(c) => d.set_item("color", c.to_array())?,
        _ => d.set_item("color", "texture")?,
    }
    d.set_item("ambient", m.ambient)?;
    d.set_item("diffuse", m.diffuse)?;
    d.set_item("specular", m.specular)?;
    d.set_item("shininess", m.shininess)?;
    d.set_item("reflection", m.reflection.to_array())?;
    d.set_item("transmission", m.transmission)?;
    d.set_item("ior", m.ior)?;
    d.set_item("fresnel", m.fresnel)?;
    d.set_item("emission", m.emission.to_array())?;
    d.set_item("bsdf", m.bsdf.is_some())?;
    Ok(d)
}

fn light_dict<'py>(py: Python<'py>, l: &Light) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match l {
        Light::Point {
            position,
            intensity,
        } => {
            d.set_item("type", "point")?;
            d.set_item("position", position.to_array())?;
            d.set_item("intensity", intensity.to_array())?;
        }
        Light::Directional {
            direction,
            irradiance,
        } => {
            d.set_item("type", "directional")?;
            d.set_item("direction", direction.to_array())?;
            d.set_item("irradiance", irradiance.to_array())?;
        }
        Light::Spot {
            position,
            direction,
            intensity,
            ..
        } => {
            d.set_item("type", "spot")?;
            d.set_item("position", position.to_array())?;
            d.set_item("direction", direction.to_array())?;
            d.set_item("intensity", intensity.to_array())?;
        }
        Light::Rect {
            corner,
            edge_u,
            edge_v,
            radiance,
            samples,
        } => {
            d.set_item("type", "rect")?;
            d.set_item("corner", corner.to_array())?;
            d.set_item("edge_u", edge_u.to_array())?;
            d.set_item("edge_v", edge_v.to_array())?;
            d.set_item("radiance", radiance.to_array())?;
            d.set_item("samples", samples)?;
        }
        Light::Sphere {
            center,
            radius,
            radiance,
            samples,
        } => {
            d.set_item("type", "sphere")?;
            d.set_item("center", center.to_array())?;
            d.set_item("radius", radius)?;
            d.set_item("radiance", radiance.to_array())?;
            d.set_item("samples", samples)?;
        }
        Light::Constant { radiance } => {
            d.set_item("type", "constant")?;
            d.set_item("radiance", radiance.to_array())?;
        }
        Light::Envmap(_) => d.set_item("type", "envmap")?,
        Light::Projector(_) => d.set_item("type", "projector")?,
    }
    Ok(d)
}

/// Sets one field of a light from Python; `i` names it in errors.
fn set_light_field(l: &mut Light, i: usize, key: &str, v: &Bound<'_, PyAny>) -> PyResult<()> {
    let field = format!("lights[{i}].{key}");
    let f = field.as_str();
    match (l, key) {
        (Light::Point { position: p, .. }, "position")
        | (Light::Spot { position: p, .. }, "position") => *p = vec3(v, f)?,
        (Light::Point { intensity: c, .. }, "intensity")
        | (Light::Spot { intensity: c, .. }, "intensity")
        | (Light::Directional { irradiance: c, .. }, "irradiance")
        | (Light::Rect { radiance: c, .. }, "radiance")
        | (Light::Sphere { radiance: c, .. }, "radiance")
        | (Light::Constant { radiance: c }, "radiance") => *c = rgb(v, f)?,
        (Light::Directional { direction: d, .. }, "direction")
        | (Light::Spot { direction: d, .. }, "direction") => {
            let x = vec3(v, f)?;
            if x.length_squared() == 0.0 {
                return Err(errors::input(format!("{f}: must not be zero")));
            }
            *d = x.normalize();
        }
        (Light::Rect { corner: p, .. }, "corner") | (Light::Sphere { center: p, .. }, "center") => {
            *p = vec3(v, f)?
        }
        (Light::Sphere { radius, .. }, "radius") => *radius = non_negative(v, f)?,
        (l, _) => {
            return Err(errors::input(format!(
                "{f}: a {} light has no editable field '{key}'",
                light_kind(l)
            )))
        }
    }
    Ok(())
}

fn light_kind(l: &Light) -> &'static str {
    match l {
        Light::Point { .. } => "point",
        Light::Directional { .. } => "directional",
        Light::Spot { .. } => "spot",
        Light::Rect { .. } => "rect",
        Light::Sphere { .. } => "sphere",
        Light::Constant { .. } => "constant",
        Light::Envmap(_) => "envmap",
        Light::Projector(_) => "projector",
    }
}

/// Sets one field of a material from Python.
fn set_material_field(m: &mut Material, key: &str, v: &Bound<'_, PyAny>) -> PyResult<()> {
    let field = format!("materials.{}.{key}", m.name);
    let f = field.as_str();
    match key {
        "color" => m.color = Texture::Solid(rgb(v, f)?),
        "ambient" => m.ambient = non_negative(v, f)?,
        "diffuse" => m.diffuse = non_negative(v, f)?,
        "specular" => m.specular = non_negative(v, f)?,
        "shininess" => m.shininess = non_negative(v, f)?,
        "reflection" => m.reflection = rgb(v, f)?,
        "transmission" => m.transmission = non_negative(v, f)?,
        "ior" => {
            let x = non_negative(v, f)?;
            if x == 0.0 {
                return Err(errors::input(format!("{f}: must be positive")));
            }
            m.ior = x
        }
        "fresnel" => {
            m.fresnel = v
                .extract()
                .map_err(|_| errors::input(format!("{f}: expected True or False")))?
        }
        "emission" => m.emission = rgb(v, f)?,
        _ => {
            return Err(errors::input(format!(
                "{f}: unknown material field (editable: color, ambient, diffuse, specular, \
                 shininess, reflection, transmission, ior, fresnel, emission)"
            )))
        }
    }
    Ok(())
}

#[pymethods]
impl PyScene {
    /// Image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.scene.settings.width
    }
    #[setter]
    fn set_width(&mut self, w: u32) -> PyResult<()> {
        self.overrides(Some(w), None, None, None)
    }
    /// Image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.scene.settings.height
    }
    #[setter]
    fn set_height(&mut self, h: u32) -> PyResult<()> {
        self.overrides(None, Some(h), None, None)
    }
    /// Samples per pixel.
    #[getter]
    fn spp(&self) -> u32 {
        self.scene.settings.spp
    }
    #[setter]
    fn set_spp(&mut self, n: u32) -> PyResult<()> {
        self.overrides(None, None, Some(n), None)
    }
    /// The deepest ray (camera rays are depth 1).
    #[getter]
    fn max_depth(&self) -> u32 {
        self.scene.settings.max_depth
    }
    #[setter]
    fn set_max_depth(&mut self, d: u32) -> PyResult<()> {
        self.overrides(None, None, None, Some(d))
    }
    /// The integrator: "whitted", "path" or "direct".
    #[getter]
    fn integrator(&self) -> &'static str {
        integrator_name(self.scene.settings.integrator)
    }
    #[setter]
    fn set_integrator(&mut self, name: &str) -> PyResult<()> {
        self.scene.settings.integrator = integrator_by_name(name)?;
        Ok(())
    }
    /// The file the scene came from (`builtin:NAME.toml` for built-ins), or None.
    #[getter]
    fn source(&self) -> Option<String> {
        self.scene.source.as_ref().map(|p| p.display().to_string())
    }
    /// The importer's warnings: features of the file read but not rendered.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    /// The camera: eye, look_at, up, projection and fov (degrees) or height.
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        camera_dict(py, &self.scene.camera)
    }
    /// The objects: name and material index, in the scene's order (object ids).
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for o in &self.scene.objects {
            let d = PyDict::new(py);
            d.set_item("name", &o.name)?;
            d.set_item("material", o.material)?;
            list.append(d)?;
        }
        Ok(list)
    }
    /// The materials, as dicts (a copy: change them with `set_material`).
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for m in &self.scene.materials {
            list.append(material_dict(py, m)?)?;
        }
        Ok(list)
    }
    /// The lights, as dicts with a "type" (a copy: change them with `set_light`).
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for l in &self.scene.lights {
            list.append(light_dict(py, l)?)?;
        }
        Ok(list)
    }
    /// What the last render measured (samples, rays, seconds, stop reason, error).
    #[getter]
    fn last_render(&self, py: Python<'_>) -> Option<Py<PyDict>> {
        self.last.as_ref().map(|d| d.clone_ref(py))
    }

    /// Moves the camera; arguments left out keep their value. `fov` is the full field
    /// of view in degrees (perspective and thin-lens cameras).
    #[pyo3(signature = (*, eye=None, look_at=None, up=None, fov=None))]
    fn set_camera(
        &mut self,
        eye: Option<Bound<'_, PyAny>>,
        look_at: Option<Bound<'_, PyAny>>,
        up: Option<Bound<'_, PyAny>>,
        fov: Option<f32>,
    ) -> PyResult<()> {
        let mut c = self.scene.camera;
        if let Some(v) = eye {
            c.eye = vec3(&v, "camera.eye")?;
        }
        if let Some(v) = look_at {
            c.look_at = vec3(&v, "camera.look_at")?;
        }
        if let Some(v) = up {
            c.up = vec3(&v, "camera.up")?;
        }
        if let Some(f) = fov {
            if !(f > 0.0 && f < 180.0) {
                return Err(errors::input(format!(
                    "camera.fov: must be between 0 and 180 degrees (got {f})"
                )));
            }
            match &mut c.projection {
                Projection::Perspective { fov_degrees, .. }
                | Projection::ThinLens { fov_degrees, .. } => *fov_degrees = f,
                Projection::Orthographic { .. } => return Err(errors::input(
                    "camera.fov: the camera is orthographic (it has a height, not a field of view)",
                )),
            }
        }
        let dir = c.look_at - c.eye;
        if dir.length_squared() == 0.0 {
            return Err(errors::input("camera: eye and look_at must differ"));
        }
        if dir.cross(c.up).length_squared() == 0.0 {
            return Err(errors::input(
                "camera.up: must not be parallel to the view direction",
            ));
        }
        self.scene.camera = c;
        Ok(())
    }

    /// Changes a material, named or by index: `set_material("red", color=(1, 0, 0),
    /// diffuse=0.8)`. Fields: color, ambient, diffuse, specular, shininess, reflection,
    /// transmission, ior, fresnel, emission (the lecture's Phong material; a
    /// physically based BSDF from another format keeps its own parameters).
    #[pyo3(signature = (key, **fields))]
    fn set_material(
        &mut self,
        key: &Bound<'_, PyAny>,
        fields: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let i = self.material_index(key)?;
        // Check every field on a copy first: a bad one changes nothing.
        let mut m = self.scene.materials[i].clone();
        if let Some(fields) = fields {
            for (k, v) in fields.iter() {
                set_material_field(&mut m, &k.extract::<String>()?, &v)?;
            }
        }
        self.scene.materials[i] = m;
        Ok(())
    }

    /// Changes light `index`: `set_light(0, position=(0, 5, 0), intensity=(10, 10, 10))`.
    /// Fields by type: point (position, intensity), spot (position, direction,
    /// intensity), directional (direction, irradiance), rect (corner, radiance),
    /// sphere (center, radius, radiance), constant (radiance).
    #[pyo3(signature = (index, **fields))]
    fn set_light(&mut self, index: usize, fields: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let n = self.scene.lights.len();
        if index >= n {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "lights[{index}]: the scene has {n} lights"
            )));
        }
        let mut l = self.scene.lights[index].clone();
        if let Some(fields) = fields {
            for (k, v) in fields.iter() {
                set_light_field(&mut l, index, &k.extract::<String>()?, &v)?;
            }
        }
        self.scene.lights[index] = l;
        Ok(())
    }

    /// Renders the scene; see `irradia.Scene.render` in the stubs for the arguments.
    #[pyo3(signature = (*, integrator=None, spp=None, threads=None, aovs=None, width=None,
        height=None, max_depth=None, tile_size=32, time=None, target_error=None, seed=None,
        checkpoint=None, resume=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn render(
        &mut self,
        py: Python<'_>,
        integrator: Option<&str>,
        spp: Option<u32>,
        threads: Option<u32>,
        aovs: Option<Bound<'_, PyAny>>,
        width: Option<u32>,
        height: Option<u32>,
        max_depth: Option<u32>,
        tile_size: u32,
        time: Option<f64>,
        target_error: Option<f64>,
        seed: Option<u32>,
        checkpoint: Option<PathBuf>,
        resume: Option<PathBuf>,
        progress: Option<PyObject>,
    ) -> PyResult<PyObject> {
        let args = crate::render::RenderArgs {
            overrides: irradia_scene::Overrides {
                width,
                height,
                spp,
                integrator: integrator.map(integrator_by_name).transpose()?,
                max_depth,
            },
            threads,
            aovs: crate::render::parse_aovs(aovs.as_ref())?,
            tile_size,
            budget: irradia_render::Budget {
                time,
                target_error,
                checkpoint,
                resume,
                seed,
            },
            progress,
        };
        crate::render::render(py, self, args)
    }

    /// The ray tree of pixel (x, y) (x right, y down from the top left), as the nested
    /// dicts of `irradia trace-pixel --format json`.
    #[pyo3(signature = (x, y, *, sample=0, integrator=None, width=None, height=None,
        spp=None, max_depth=None))]
    #[allow(clippy::too_many_arguments)]
    fn trace_pixel(
        &mut self,
        py: Python<'_>,
        x: u32,
        y: u32,
        sample: u32,
        integrator: Option<&str>,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
    ) -> PyResult<PyObject> {
        let overrides = irradia_scene::Overrides {
            width,
            height,
            spp,
            integrator: integrator.map(integrator_by_name).transpose()?,
            max_depth,
        };
        let doc = self.with_overrides(&overrides, |scene| {
            py.allow_threads(|| {
                let (tree, radiance) =
                    irradia_render::trace_pixel(scene, x, y, sample).map_err(errors::render)?;
                Ok(irradia_render::raytree::pixel_document(
                    x, y, sample, radiance, &tree,
                ))
            })
        })?;
        json_to_py(py, &doc)
    }

    /// Casts rays (Open3D's `RaycastingScene.cast_rays`): `rays` of shape (..., 6)
    /// (origin, direction), or `rays` = origins and `directions` both (..., 3).
    /// Returns a dict of arrays: t_hit, geometry_ids, primitive_ids, primitive_uvs,
    /// primitive_normals.
    #[pyo3(signature = (rays, directions=None, *, t_max=None, threads=None))]
    fn cast_rays(
        &self,
        py: Python<'_>,
        rays: PyReadonlyArrayDyn<'_, f32>,
        directions: Option<PyReadonlyArrayDyn<'_, f32>>,
        t_max: Option<f32>,
        threads: Option<u32>,
    ) -> PyResult<PyObject> {
        crate::raycast::cast_rays(py, &self.scene, rays, directions, t_max, threads, true)
    }

    /// `cast_rays` with every ray traced alone through the scene's hierarchy
    /// (`Accel::intersect_cast`, no packets): the reference the batched path must
    /// equal bit for bit (tests/test_cast_rays.py).
    #[pyo3(signature = (rays, *, t_max=None, threads=None))]
    fn _cast_rays_single(
        &self,
        py: Python<'_>,
        rays: PyReadonlyArrayDyn<'_, f32>,
        t_max: Option<f32>,
        threads: Option<u32>,
    ) -> PyResult<PyObject> {
        crate::raycast::cast_rays(py, &self.scene, rays, None, t_max, threads, false)
    }

    /// Seconds the ray kernel alone takes on `rays` (..., 6) (no numpy in or out):
    /// the benchmark's reference for what `cast_rays` adds (bench/python).
    /// `packets=False` traces every ray alone (the path before packet traversal), for
    /// paired timings.
    #[pyo3(signature = (rays, *, threads=None, packets=true))]
    fn _cast_rays_kernel_seconds(
        &self,
        py: Python<'_>,
        rays: PyReadonlyArrayDyn<'_, f32>,
        threads: Option<u32>,
        packets: bool,
    ) -> PyResult<f64> {
        crate::raycast::kernel_seconds(py, &self.scene, rays, threads, packets)
    }

    fn __repr__(&self) -> String {
        let s = &self.scene.settings;
        format!(
            "<irradia.Scene {} {}x{} {} spp, {} objects, {} lights, {}>",
            self.source().unwrap_or_else(|| "(no file)".into()),
            s.width,
            s.height,
            s.spp,
            self.scene.objects.len(),
            self.scene.lights.len(),
            integrator_name(s.integrator)
        )
    }
}

impl PyScene {
    fn overrides(
        &mut self,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
    ) -> PyResult<()> {
        let o = irradia_scene::Overrides {
            width,
            height,
            spp,
            integrator: None,
            max_depth,
        };
        let saved = self.scene.settings.clone();
        o.apply(&mut self.scene).map_err(|e| {
            self.scene.settings = saved;
            errors::scene(e)
        })
    }

    /// Runs `f` on the scene with `overrides` applied, then puts the settings back.
    pub fn with_overrides<T>(
        &mut self,
        overrides: &irradia_scene::Overrides,
        f: impl FnOnce(&Scene) -> PyResult<T>,
    ) -> PyResult<T> {
        let saved = self.scene.settings.clone();
        let r = match overrides.apply(&mut self.scene) {
            Ok(()) => f(&self.scene),
            Err(e) => Err(errors::scene(e)),
        };
        self.scene.settings = saved;
        r
    }

    fn material_index(&self, key: &Bound<'_, PyAny>) -> PyResult<usize> {
        let ms = &self.scene.materials;
        if let Ok(i) = key.extract::<usize>() {
            return if i < ms.len() {
                Ok(i)
            } else {
                Err(pyo3::exceptions::PyIndexError::new_err(format!(
                    "materials[{i}]: the scene has {} materials",
                    ms.len()
                )))
            };
        }
        let name: String = key
            .extract()
            .map_err(|_| errors::input("a material is named by its name or index"))?;
        ms.iter().position(|m| m.name == name).ok_or_else(|| {
            let names: Vec<&str> = ms.iter().map(|m| m.name.as_str()).collect();
            pyo3::exceptions::PyKeyError::new_err(format!(
                "unknown material '{name}'; the scene's materials are: {}",
                names.join(", ")
            ))
        })
    }
}
