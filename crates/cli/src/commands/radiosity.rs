//! `irradia radiosity`: solve a scene (or the measured Cornell box) by radiosity and
//! write an image, the solved mesh (PLY) and the residual history.

use crate::error::CliError;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use irradia_radiosity::display::{render_gouraud, write_ply, View};
use irradia_radiosity::formfactor::{Method, Params};
use irradia_radiosity::mesh::MeshOptions;
use irradia_radiosity::pipeline::{self, Config, Progress};
use irradia_radiosity::solver::hierarchical::HierarchicalOptions;
use irradia_radiosity::solver::{SolveOptions, SolverKind};
use irradia_radiosity::two_pass::{TwoPass, TwoPassOptions};
use irradia_radiosity::two_pass_scene::{self, SpecularScene};
use irradia_radiosity::{convergence, scenes, RadiosityError};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

const EXAMPLES: &str = "\
Examples:
  irradia radiosity                                   # measured Cornell box -> radiosity.png
  irradia radiosity --elements 4000 --form-factors raycast --solver southwell -o box.png
  irradia radiosity --solver hierarchical --max-element-area 100 --mesh-out box.ply
  irradia radiosity --builtin cornell-empty --form-factors hemicube --hemicube-resolution 256
  irradia radiosity --elements 500 --convergence residuals.csv   # also residuals.png
  irradia radiosity scene.toml --max-element-area 0.01 -o scene.png
  irradia radiosity --builtin cornell-specular --display two-pass -o specular.png
  irradia radiosity docs/examples/two-pass.toml --display two-pass -o two-pass.png

Built-in scenes: cornell (the measured Cornell box with its blocks; the default),
cornell-empty (without the blocks), furnace (a closed glowing cube, b = 2),
cornell-specular (the empty box with a mirror sphere and a glass sphere, for
--display two-pass); other names are looked up among the ray tracer's built-ins (see
`irradia scenes`).
Displays: gouraud (the default) draws the vertex radiosity with the software
rasterizer; two-pass traces rays from the eye, reading the same vertex radiosity at
diffuse hits and following mirrors and glass (in the radiosity pass mirrors are black
occluders and glass is left out). In a scene file, with --display two-pass, an object
whose material has no emission and a mirror `reflection` or `transmission` at least
its diffuse reflectance (color x diffuse) is traced: glass when transmission > 0
(Fresnel at `ior`, filtered by transmission x filter), else a mirror (docs/radiosity.md).
Units of the Cornell box are millimetres (--max-element-area 100 is 10 mm x 10 mm).
Pixel values are radiance b/pi. Exit codes: 0 done, 1 failure, 2 bad input.";

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormFactorArg {
    /// Point-to-polygon closed form with Gauss quadrature over the sender.
    Analytic,
    /// Point-to-polygon closed form at element centroids.
    Contour,
    /// Nusselt analogue by ray casting.
    Hemisphere,
    /// Hemicube with precomputed delta form factors (z-buffer item buffer).
    Hemicube,
    /// Wallace et al. 1989: sample points on the source to receiving vertices.
    Raycast,
    /// Monte Carlo area to area.
    Montecarlo,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DisplayArg {
    /// Vertex radiosity interpolated across triangles by the software rasterizer.
    Gouraud,
    /// Ray traced from the eye: solved radiosity at diffuse hits, mirrors and glass
    /// followed recursively.
    TwoPass,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SolverArg {
    /// Dense LU (reference, small meshes).
    Direct,
    Jacobi,
    GaussSeidel,
    /// Neumann series with its truncation bound.
    Series,
    /// Progressive refinement by shooting, with the ambient term.
    Southwell,
    /// Hanrahan-Salzman-Aupperle, BF refinement, no n² matrix.
    Hierarchical,
}

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct RadiosityArgs {
    /// Scene file (TOML or JSON). Without it (and without --builtin): the measured
    /// Cornell box.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// A built-in scene: cornell, cornell-empty, furnace, cornell-specular, or a
    /// ray-tracer built-in.
    #[arg(long, value_name = "NAME")]
    pub builtin: Option<String>,
    /// Form-factor method (matrix solvers).
    #[arg(long = "form-factors", value_enum, default_value = "hemicube")]
    pub form_factors: FormFactorArg,
    #[arg(long, value_enum, default_value = "gauss-seidel")]
    pub solver: SolverArg,
    /// Largest element area, in scene units squared.
    #[arg(long, value_name = "A")]
    pub max_element_area: Option<f64>,
    /// About this many elements (sets the element area from the scene's total area);
    /// used when --max-element-area is not given.
    #[arg(long, value_name = "N", default_value_t = 1000)]
    pub elements: usize,
    /// Refuse to make more elements than this.
    #[arg(long, value_name = "N", default_value_t = 2_000_000)]
    pub element_limit: usize,
    /// Hemicube pixels across the top face.
    #[arg(long, value_name = "N", default_value_t = 128)]
    pub hemicube_resolution: usize,
    /// Hemisphere (Nusselt) cells across the unit disk.
    #[arg(long, value_name = "N", default_value_t = 64)]
    pub hemisphere_resolution: usize,
    /// Ray casting: sample points on the source per receiving vertex.
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub rays: usize,
    /// Monte Carlo: point pairs per element pair.
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub samples: usize,
    /// Analytic/contour: shadow rays per element pair (0: no occlusion).
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub visibility_samples: usize,
    /// Stop when the relative residual is below this.
    #[arg(long, value_name = "T", default_value_t = 1e-6)]
    pub tolerance: f64,
    #[arg(long, value_name = "N", default_value_t = 10_000)]
    pub max_iterations: usize,
    /// Hierarchical: refine links while B·F exceeds this times the largest emission.
    #[arg(long, value_name = "E", default_value_t = 1e-4)]
    pub bf_epsilon: f64,
    /// Hierarchical: shadow rays per link.
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub link_rays: usize,
    /// Rounds of adaptive subdivision where radiosity changes fast (matrix solvers).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub adaptive: usize,
    /// The scene is a closed room: check that every edge of every surface is shared
    /// (an open edge is an error naming the object, with its file and line).
    #[arg(long)]
    pub closed: bool,
    /// Output image (.png, .exr, .pfm): radiance b/pi, drawn as --display says.
    #[arg(short, long, value_name = "FILE", default_value = "radiosity.png")]
    pub output: PathBuf,
    /// How the image is made: gouraud (rasterized vertex radiosity) or two-pass
    /// (ray traced, with mirrors and glass).
    #[arg(long, value_enum, default_value = "gouraud")]
    pub display: DisplayArg,
    /// Two-pass display: rays per pixel along each axis (N² per pixel).
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub pixel_samples: u32,
    #[arg(long, value_name = "W", default_value_t = 512)]
    pub width: u32,
    #[arg(long, value_name = "H", default_value_t = 512)]
    pub height: u32,
    /// Also write the solved mesh as PLY with vertex colours.
    #[arg(long, value_name = "FILE.ply")]
    pub mesh_out: Option<PathBuf>,
    /// Write the residual per iteration of every matrix solver as CSV, and a chart
    /// comparing them next to it (same name, .png).
    #[arg(long, value_name = "FILE.csv")]
    pub convergence: Option<PathBuf>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

struct Bar {
    bar: Option<ProgressBar>,
    phase: Mutex<String>,
}

impl Progress for Bar {
    fn phase(&self, name: &str, total: u64) {
        *self.phase.lock().unwrap() = name.to_string();
        if let Some(b) = &self.bar {
            b.set_length(total.max(1));
            b.set_position(0);
            b.set_message(name.to_string());
        }
    }
    fn set(&self, done: u64) {
        if let Some(b) = &self.bar {
            b.set_position(done);
        }
    }
}

fn err(e: RadiosityError) -> CliError {
    match e {
        RadiosityError::Input(m) => CliError::Input(m),
        RadiosityError::Failure(m) => CliError::Failure(m),
    }
}

pub fn run(a: RadiosityArgs) -> Result<(), CliError> {
    for (name, v) in [
        ("--hemicube-resolution", a.hemicube_resolution),
        ("--hemisphere-resolution", a.hemisphere_resolution),
        ("--rays", a.rays),
        ("--samples", a.samples),
        ("--elements", a.elements),
        ("--pixel-samples", a.pixel_samples as usize),
    ] {
        if v == 0 {
            return Err(CliError::Input(format!("{name} must be at least 1")));
        }
    }
    if a.pixel_samples > 64 {
        return Err(CliError::Input(format!(
            "--pixel-samples {} would trace {} rays per pixel; use at most 64",
            a.pixel_samples,
            a.pixel_samples as u64 * a.pixel_samples as u64
        )));
    }
    if !(a.tolerance > 0.0) || !(a.bf_epsilon > 0.0) {
        return Err(CliError::Input(
            "--tolerance and --bf-epsilon must be positive".into(),
        ));
    }
    irradia_core::image::check_size(a.width, a.height, 12)
        .map_err(|e| CliError::Input(e.to_string()))?;
    // The scene.
    let mut view = View::cornell(a.width, a.height);
    let mut warnings = Vec::new();
    let mut specular: Option<SpecularScene> = None;
    let specs = match (&a.scene, &a.builtin) {
        (Some(_), Some(_)) => {
            return Err(CliError::Input(
                "give either a scene file or --builtin, not both".into(),
            ))
        }
        (None, None) => scenes::cornell_measured(),
        (None, Some(name)) => match scenes::builtin(name) {
            None if two_pass_scene::builtin(name).is_some() => {
                let s = two_pass_scene::builtin(name).expect("checked");
                let patches = s.patches.clone();
                specular = Some(s);
                patches
            }
            Some(s) => {
                if name == "furnace" {
                    view = View {
                        eye: glam::DVec3::new(0.5, 0.5, 0.05),
                        target: glam::DVec3::new(0.5, 0.5, 1.0),
                        up: glam::DVec3::Y,
                        fov_y: 60.0,
                        width: a.width,
                        height: a.height,
                    };
                }
                s
            }
            None => {
                let scene = irradia_scene::builtin::load(name)?;
                view = view_of(&scene, a.width, a.height)?;
                let (s, w) = if a.display == DisplayArg::TwoPass {
                    let (ss, _, w) = two_pass_scene::from_scene(&scene, 32).map_err(err)?;
                    let patches = ss.patches.clone();
                    specular = Some(ss);
                    (patches, w)
                } else {
                    irradia_radiosity::scene_input::patches_from_scene(&scene, 32).map_err(err)?
                };
                warnings.extend(w);
                s
            }
        },
        (Some(path), None) => {
            if !path.exists() {
                return Err(CliError::Input(format!(
                    "{}: no such scene file",
                    path.display()
                )));
            }
            let scene = irradia_scene::load_file(path)?;
            view = view_of(&scene, a.width, a.height)?;
            let (s, objects, w) = if a.display == DisplayArg::TwoPass {
                // Mirrors and glass (by their materials) are traced in pass two.
                let (ss, objects, w) = two_pass_scene::from_scene(&scene, 32).map_err(err)?;
                let patches = ss.patches.clone();
                specular = Some(ss);
                (patches, objects, w)
            } else {
                irradia_radiosity::scene_input::patches_with_objects(&scene, 32).map_err(err)?
            };
            if a.closed {
                irradia_radiosity::scene_input::check_closed(&s, Some((&scene, &objects)))
                    .map_err(err)?;
            }
            warnings.extend(w);
            s
        }
    };
    let total_area: f64 = specs
        .iter()
        .map(|s| {
            irradia_radiosity::geom::Poly::from_slice(&s.corners[..s.corners.len().min(4)])
                .map(|p| p.area())
                .unwrap_or(0.0)
        })
        .sum();
    let area = a.max_element_area.unwrap_or(total_area / a.elements as f64);
    if !(area > 0.0) || !area.is_finite() {
        return Err(CliError::Input(format!(
            "--max-element-area must be a positive number (got {area})"
        )));
    }
    let solver = match a.solver {
        SolverArg::Direct => SolverKind::Direct,
        SolverArg::Jacobi => SolverKind::Jacobi,
        SolverArg::GaussSeidel => SolverKind::GaussSeidel,
        SolverArg::Series => SolverKind::Series,
        SolverArg::Southwell => SolverKind::Southwell,
        SolverArg::Hierarchical => SolverKind::Hierarchical,
    };
    let method = match a.form_factors {
        FormFactorArg::Analytic => Method::Analytic,
        FormFactorArg::Contour => Method::Contour,
        FormFactorArg::Hemisphere => Method::Hemisphere,
        FormFactorArg::Hemicube => Method::Hemicube,
        FormFactorArg::Raycast => Method::RayCast,
        FormFactorArg::Montecarlo => Method::MonteCarlo,
    };
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(area),
            max_elements: a.element_limit,
        },
        method,
        params: Params {
            hemicube_resolution: a.hemicube_resolution,
            hemisphere_resolution: a.hemisphere_resolution,
            rays: a.rays,
            samples: a.samples,
            visibility_samples: a.visibility_samples,
            gauss_points: 3,
            seed: a.seed,
        },
        solver,
        solve: SolveOptions {
            tolerance: a.tolerance,
            max_iterations: a.max_iterations,
        },
        hierarchical: HierarchicalOptions {
            bf_epsilon: a.bf_epsilon,
            // --elements N: the leaf area that gives N leaves.
            target_leaves: a.max_element_area.is_none().then_some(a.elements),
            visibility_rays: a.link_rays,
            tolerance: a.tolerance,
            max_iterations: a.max_iterations,
            seed: a.seed,
            ..Default::default()
        },
        compare_solvers: a.convergence.is_some() && solver != SolverKind::Hierarchical,
        adaptive_rounds: a.adaptive,
        ..Default::default()
    };
    let show = !a.quiet && std::io::stderr().is_terminal();
    let bar = Bar {
        bar: show.then(|| {
            let b = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({eta})")
                    .unwrap()
                    .progress_chars("=> "),
            );
            b
        }),
        phase: Mutex::new(String::new()),
    };
    for w in &warnings {
        eprintln!("irradia: warning: {w}");
    }
    let report = pipeline::run(&specs, &cfg, &bar).map_err(err)?;
    if let Some(b) = &bar.bar {
        b.finish_and_clear();
    }
    let t = Instant::now();
    let dm = report.display_mesh();
    let img = match a.display {
        DisplayArg::Gouraud => {
            if specular.is_some() && !a.quiet {
                eprintln!(
                    "irradia: note: the Gouraud image shows mirrors as their black stand-ins and no glass; \
                     --display two-pass traces them"
                );
            }
            render_gouraud(&dm, &view).map_err(err)?
        }
        DisplayArg::TwoPass => {
            let objects = specular.as_ref().map_or(&[][..], |s| &s.objects[..]);
            let keep = |p: u32| {
                let source = report.mesh.patches[p as usize].source;
                !specular.as_ref().is_some_and(|s| s.is_stand_in(source))
            };
            let tracer = TwoPass::new(&dm, keep, objects).map_err(err)?;
            let opts = TwoPassOptions {
                samples_per_axis: a.pixel_samples,
                ..Default::default()
            };
            tracer.render(&view, &opts).map_err(err)?
        }
    };
    irradia_core::io::save(&img, &a.output)
        .map_err(|e| CliError::Failure(format!("{}: {e}", a.output.display())))?;
    if let Some(p) = &a.mesh_out {
        write_ply(&dm, p).map_err(err)?;
    }
    let display_time = t.elapsed();
    if let Some(p) = &a.convergence {
        let hs: Vec<convergence::History> = report
            .histories
            .iter()
            .map(|(n, r)| convergence::History {
                name: n,
                residuals: r,
            })
            .collect();
        convergence::write_csv(p, &hs).map_err(err)?;
        let chart = p.with_extension("png");
        convergence::write_chart(
            &chart,
            &hs,
            &format!("radiosity residuals, {} elements", report.mesh.len()),
        )
        .map_err(err)?;
        if !a.quiet {
            eprintln!("convergence: {} and {}", p.display(), chart.display());
        }
    }
    for n in &report.notes {
        if n.starts_with("warning") {
            eprintln!("irradia: {n}");
        }
    }
    if !a.quiet {
        eprintln!(
            "{} patches, {} elements; solver {}",
            report.mesh.patches.len(),
            report.mesh.len(),
            solver.name()
        );
        if let Some(d) = report.diagnostics {
            eprintln!("form factors ({}): {d}", method.name());
        }
        for n in report.notes.iter().filter(|n| !n.starts_with("warning")) {
            eprintln!("{n}");
        }
        let mut total = display_time;
        for (phase, d) in &report.timings {
            eprintln!("  {phase:<44} {:>9.3} s", d.as_secs_f64());
            total += *d;
        }
        eprintln!(
            "  {:<44} {:>9.3} s",
            match a.display {
                DisplayArg::Gouraud => "display (Gouraud image, PLY)",
                DisplayArg::TwoPass => "display (two-pass image, PLY)",
            },
            display_time.as_secs_f64()
        );
        eprintln!("  {:<44} {:>9.3} s", "total", total.as_secs_f64());
        eprintln!(
            "final relative residual {:.3e}; image {}",
            report.solution.residual,
            a.output.display()
        );
    }
    Ok(())
}

fn view_of(scene: &irradia_scene::Scene, width: u32, height: u32) -> Result<View, CliError> {
    let c = &scene.camera;
    let Some(fov_y) = c.fov_y_radians(width, height) else {
        return Err(CliError::Input(
            "radiosity images need a perspective camera; the scene's is orthographic".into(),
        ));
    };
    let fov_y = (fov_y as f64).to_degrees();
    Ok(View {
        eye: c.eye.as_dvec3(),
        target: c.look_at.as_dvec3(),
        up: c.up.as_dvec3(),
        fov_y,
        width,
        height,
    })
}
