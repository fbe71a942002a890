//! One `irradia radiosity` job as library calls: the scene chosen by name or file
//! ([`load_scene`]: the radiosity built-ins, the two-pass built-in, the ray tracer's
//! built-ins and scene files, with the mirrors and glass of a two-pass display set
//! aside), the image of the solved mesh ([`display_image`]: Gouraud through the
//! rasterizer, or the two-pass ray tracer of Wallace, Cohen and Greenberg 1987), the
//! convergence table and chart, and the summary of the report ([`summary_lines`]).
//! [`crate::pipeline::run`] does the meshing, form factors and solve in between.

use crate::convergence;
use crate::display::{render_gouraud, View};
use crate::error::{RadiosityError, Result};
use crate::formfactor::Method;
use crate::mesh::PatchSpec;
use crate::pipeline::Report;
use crate::solver::SolverKind;
use crate::two_pass::{TwoPass, TwoPassOptions};
use crate::two_pass_scene::{self, SpecularScene};
use crate::{scene_input, scenes};
use irradia_core::Image;
use irradia_scene::{Scene, SceneError};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Facets per curved object when a scene's shapes become patches.
pub const DETAIL: u32 = 32;

/// Where the scene comes from.
#[derive(Debug)]
pub enum SceneSource<'a> {
    /// The measured Cornell box (no file, no `--builtin`).
    Default,
    /// A built-in by name: [`scenes::BUILTINS`], `cornell-specular`, or one of the ray
    /// tracer's built-ins.
    Builtin(&'a str),
    /// A scene file (TOML or JSON).
    File(&'a Path),
    /// A scene already read (by `irradia_import`, from any format it reads).
    Scene(Box<Scene>),
}

/// How the solved radiosity becomes an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Display {
    /// Vertex radiosity interpolated across triangles by the software rasterizer.
    Gouraud,
    /// Ray traced from the eye with `samples_per_axis`² rays per pixel: the solved
    /// radiosity at diffuse hits, mirrors and glass followed.
    TwoPass { samples_per_axis: u32 },
}

impl Display {
    /// The display's line in the timing table.
    pub fn label(&self) -> &'static str {
        match self {
            Display::Gouraud => "display (Gouraud image, PLY)",
            Display::TwoPass { .. } => "display (two-pass image, PLY)",
        }
    }
}

/// The camera of a scene that has none of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuiltinView {
    /// The Cornell box's measured camera.
    Cornell,
    /// Inside the furnace cube, looking at its back wall.
    Furnace,
}

impl BuiltinView {
    pub fn view(self, width: u32, height: u32) -> View {
        match self {
            BuiltinView::Cornell => View::cornell(width, height),
            BuiltinView::Furnace => View {
                eye: glam::DVec3::new(0.5, 0.5, 0.05),
                target: glam::DVec3::new(0.5, 0.5, 1.0),
                up: glam::DVec3::Y,
                fov_y: 60.0,
                width,
                height,
            },
        }
    }
}

/// The scene of a job.
pub struct JobScene {
    /// The diffuse patches the radiosity pass solves.
    pub specs: Vec<PatchSpec>,
    /// With a two-pass display (or the specular built-in): the mirrors and glass.
    pub specular: Option<SpecularScene>,
    /// The ray tracer's scene (a file or one of its built-ins), whose camera is the view.
    pub scene: Option<Scene>,
    /// The camera of a radiosity built-in (when `scene` is `None`).
    pub view: BuiltinView,
    /// What the translation to patches left out or changed.
    pub warnings: Vec<String>,
}

/// Every name `--builtin` accepts, with a line about it: the radiosity built-ins, the
/// specular Cornell box, then the ray tracer's built-ins.
pub fn builtin_names() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = scenes::BUILTINS
        .iter()
        .map(|(n, d)| (n.to_string(), d.to_string()))
        .collect();
    v.push((
        "cornell-specular".into(),
        "the empty box with a mirror sphere and a glass sphere (for --display two-pass)".into(),
    ));
    for (n, d) in irradia_scene::builtin::names() {
        // A radiosity built-in of the same name comes first (`cornell`).
        if !v.iter().any(|(m, _)| m == n) {
            v.push((n.to_string(), format!("ray tracer built-in: {d}")));
        }
    }
    v
}

fn scene_error(e: SceneError) -> RadiosityError {
    if e.is_bad_input() {
        RadiosityError::Input(e.to_string())
    } else {
        RadiosityError::Failure(e.to_string())
    }
}

/// Loads the scene of a job: its patches, and with `two_pass` its mirrors and glass;
/// with `closed`, a scene file must be a closed room (every edge shared).
pub fn load_scene(source: SceneSource<'_>, two_pass: bool, closed: bool) -> Result<JobScene> {
    let mut job = JobScene {
        specs: Vec::new(),
        specular: None,
        scene: None,
        view: BuiltinView::Cornell,
        warnings: Vec::new(),
    };
    match source {
        SceneSource::Default => job.specs = scenes::cornell_measured(),
        SceneSource::Builtin(name) => {
            if let Some(s) = scenes::builtin(name) {
                job.specs = s;
                if name == "furnace" {
                    job.view = BuiltinView::Furnace;
                }
            } else if let Some(s) = two_pass_scene::builtin(name) {
                job.specs = s.patches.clone();
                job.specular = Some(s);
            } else if irradia_scene::builtin::source(name).is_some() {
                let scene = irradia_scene::builtin::load(name).map_err(scene_error)?;
                take_scene(&mut job, scene, two_pass, false)?;
            } else {
                let names: Vec<String> = builtin_names().into_iter().map(|(n, _)| n).collect();
                return Err(RadiosityError::Input(format!(
                    "--builtin {name:?}: unknown built-in scene; the names are {}",
                    names.join(", ")
                )));
            }
        }
        SceneSource::File(path) => {
            let scene = irradia_scene::load_file(path).map_err(scene_error)?;
            take_scene(&mut job, scene, two_pass, closed)?;
        }
        SceneSource::Scene(scene) => take_scene(&mut job, *scene, two_pass, closed)?,
    }
    Ok(job)
}

/// The patches of a scene the caller keeps (the Python binding's `Scene`), checked
/// closed when asked, with the translation's warnings.
pub fn patches_of(scene: &Scene, closed: bool) -> Result<(Vec<PatchSpec>, Vec<String>)> {
    let (specs, objects, w) = scene_input::patches_with_objects(scene, DETAIL)?;
    if closed {
        scene_input::check_closed(&specs, Some((scene, &objects)))?;
    }
    Ok((specs, w))
}

/// Makes `scene` the job's: its patches (checked closed when asked) and warnings.
fn take_scene(job: &mut JobScene, scene: Scene, two_pass: bool, closed: bool) -> Result<()> {
    let (specs, objects, w) = scene_patches(&scene, two_pass, job)?;
    if closed {
        scene_input::check_closed(&specs, Some((&scene, &objects)))?;
    }
    job.specs = specs;
    job.warnings.extend(w);
    job.scene = Some(scene);
    Ok(())
}

/// A scene's patches, the object of each, and the warnings; with `two_pass` the
/// mirrors and glass (by their materials) go to `job.specular`, to be traced in pass two.
fn scene_patches(
    scene: &Scene,
    two_pass: bool,
    job: &mut JobScene,
) -> Result<(Vec<PatchSpec>, Vec<usize>, Vec<String>)> {
    if two_pass {
        let (ss, objects, w) = two_pass_scene::from_scene(scene, DETAIL)?;
        let patches = ss.patches.clone();
        job.specular = Some(ss);
        Ok((patches, objects, w))
    } else {
        scene_input::patches_with_objects(scene, DETAIL)
    }
}

/// The total area of the patches (the first four corners of each), for `--elements`.
pub fn total_area(specs: &[PatchSpec]) -> f64 {
    specs
        .iter()
        .map(|s| {
            crate::geom::Poly::from_slice(&s.corners[..s.corners.len().min(4)])
                .map(|p| p.area())
                .unwrap_or(0.0)
        })
        .sum()
}

/// The image of the solved mesh seen from `view`.
pub fn display_image(
    report: &Report,
    display: Display,
    specular: Option<&SpecularScene>,
    view: &View,
) -> Result<Image> {
    let dm = report.display_mesh();
    match display {
        Display::Gouraud => render_gouraud(&dm, view),
        Display::TwoPass { samples_per_axis } => {
            let objects = specular.map_or(&[][..], |s| &s.objects[..]);
            let keep = |p: u32| {
                let source = report.mesh.patches[p as usize].source;
                !specular.is_some_and(|s| s.is_stand_in(source))
            };
            let tracer = TwoPass::new(&dm, keep, objects)?;
            let opts = TwoPassOptions {
                samples_per_axis,
                ..Default::default()
            };
            tracer.render(view, &opts)
        }
    }
}

/// Writes the residual history of every solver as CSV at `path` and a chart beside it
/// (same name, .png); returns the chart's path.
pub fn write_convergence(path: &Path, report: &Report) -> Result<PathBuf> {
    let hs: Vec<convergence::History> = report
        .histories
        .iter()
        .map(|(n, r)| convergence::History {
            name: n,
            residuals: r,
        })
        .collect();
    convergence::write_csv(path, &hs)?;
    let chart = path.with_extension("png");
    convergence::write_chart(
        &chart,
        &hs,
        &format!("radiosity residuals, {} elements", report.mesh.len()),
    )?;
    Ok(chart)
}

/// The summary after a job, one line each: the mesh and solver, the form-factor
/// diagnostics, the notes, the time of every phase and the total, the final residual.
pub fn summary_lines(
    report: &Report,
    solver: SolverKind,
    method: Method,
    display: Display,
    display_time: Duration,
    output: &Path,
) -> Vec<String> {
    let mut lines = vec![format!(
        "{} patches, {} elements; solver {}",
        report.mesh.patches.len(),
        report.mesh.len(),
        solver.name()
    )];
    if let Some(d) = &report.diagnostics {
        lines.push(format!("form factors ({}): {d}", method.name()));
    }
    lines.extend(
        report
            .notes
            .iter()
            .filter(|n| !n.starts_with("warning"))
            .cloned(),
    );
    let mut total = display_time;
    for (phase, d) in &report.timings {
        lines.push(format!("  {phase:<44} {:>9.3} s", d.as_secs_f64()));
        total += *d;
    }
    lines.push(format!(
        "  {:<44} {:>9.3} s",
        display.label(),
        display_time.as_secs_f64()
    ));
    lines.push(format!("  {:<44} {:>9.3} s", "total", total.as_secs_f64()));
    lines.push(format!(
        "final relative residual {:.3e}; image {}",
        report.solution.residual,
        output.display()
    ));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_name_loads() {
        for (name, _) in builtin_names() {
            let j = load_scene(SceneSource::Builtin(&name), false, false);
            // A ray-tracer built-in may hold nothing radiosity can mesh; it must still
            // be a named scene, not "unknown".
            if let Err(e) = &j {
                assert!(!e.to_string().contains("unknown built-in"), "{name}: {e}");
            }
        }
        let e = load_scene(SceneSource::Builtin("nope"), false, false)
            .err()
            .expect("unknown");
        let m = e.to_string();
        assert!(e.is_input() && m.contains("cornell-specular") && m.contains("whitted"));
    }

    #[test]
    fn furnace_has_its_own_view_and_the_specular_box_its_objects() {
        let f = load_scene(SceneSource::Builtin("furnace"), false, false).unwrap();
        assert_eq!(f.view, BuiltinView::Furnace);
        let s = load_scene(SceneSource::Builtin("cornell-specular"), false, false).unwrap();
        assert_eq!(s.specular.as_ref().map(|s| s.objects.len()), Some(2));
        assert!(total_area(&s.specs) > 0.0);
    }
}
