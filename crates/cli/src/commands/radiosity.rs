//! `irradia radiosity`: solve a scene (or the measured Cornell box) by radiosity and
//! write an image, the solved mesh (PLY) and the residual history. The job itself is
//! `irradia_radiosity::job` and `pipeline`; this file maps the options onto them.

use crate::error::CliError;
use crate::output;
use crate::progress::Progress;
use clap::{Args, ValueEnum};
use irradia_radiosity::display::{write_ply, View};
use irradia_radiosity::formfactor::Method;
use irradia_radiosity::job::{self, Display, SceneSource};
use irradia_radiosity::options::JobOptions;
use irradia_radiosity::pipeline;
use irradia_radiosity::solver::SolverKind;
use irradia_radiosity::RadiosityError;
use std::path::PathBuf;
use std::time::Instant;

const EXAMPLES: &str = "\
Examples:
  irradia radiosity                                   # measured Cornell box -> radiosity.png
  irradia radiosity --elements 4000 --form-factors raycast --solver southwell -o box.png
  irradia radiosity --solver hierarchical --max-element-area 100 --mesh-out box.ply
  irradia radiosity --builtin cornell-empty --form-factors hemicube --hemicube-resolution 256
  irradia radiosity --elements 500 --convergence residuals.csv   # also residuals.png
  irradia radiosity docs/examples/two-pass.toml --max-element-area 0.01 -o scene.png
  irradia radiosity --builtin cornell-specular --display two-pass -o specular.png
  irradia radiosity docs/examples/two-pass.toml --display two-pass -o two-pass.png
  irradia radiosity --solver hierarchical --elements 20000 --comm local --ranks 2
  mpirun -np 4 irradia radiosity --solver hierarchical --elements 20000 --comm mpi -o h.png

Displays: gouraud (the default) draws the vertex radiosity with the software
rasterizer; two-pass traces rays from the eye, reading the same vertex radiosity at
diffuse hits and following mirrors and glass (in the radiosity pass mirrors are black
occluders and glass is left out). In a scene file, with --display two-pass, an object
whose material has no emission and a mirror `reflection` or `transmission` at least
its diffuse reflectance (color x diffuse) is traced: glass when transmission > 0
(Fresnel at `ior`, filtered by transmission x filter), else a mirror (docs/radiosity.md).
Units of the Cornell box are millimetres (--max-element-area 100 is 10 mm x 10 mm).
Pixel values are radiance b/pi. Exit codes: 0 done, 1 failure, 2 bad input.";

/// The examples, then every scene `--builtin` accepts.
fn after_help() -> String {
    let mut s = format!("{EXAMPLES}\n\nBuilt-in scenes (--builtin NAME):\n");
    for (name, what) in job::builtin_names() {
        s.push_str(&format!("  {name:<18} {what}\n"));
    }
    s
}

/// The `--builtin` option's own help: every name.
fn builtin_help() -> String {
    let names: Vec<String> = job::builtin_names().into_iter().map(|(n, _)| n).collect();
    format!(
        "A built-in scene instead of a file: {} (see the list below)",
        names.join(", ")
    )
}

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
#[command(after_long_help = after_help())]
pub struct RadiosityArgs {
    /// Scene file (TOML or JSON). Without it (and without --builtin): the measured
    /// Cornell box.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// A built-in scene: cornell, cornell-empty, furnace, cornell-specular, or a
    /// ray-tracer built-in (the list is at the end of --help).
    #[arg(long, value_name = "NAME", long_help = builtin_help())]
    pub builtin: Option<String>,
    #[command(flatten)]
    pub import: crate::scene_arg::ImportArgs,
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
    #[command(flatten)]
    pub comm: super::render_comm::CommArgs,
    /// Print nothing but errors (no progress, no summary).
    #[arg(short, long, help_heading = "General options")]
    pub quiet: bool,
}

/// The pipeline's progress callbacks drawn by the shared reporter.
struct Phases(Progress);

impl pipeline::Progress for Phases {
    fn phase(&self, name: &str, total: u64) {
        self.0.phase(name, (total > 0).then_some(total));
    }
    fn set(&self, done: u64) {
        self.0.set_position(done);
    }
}

fn err(e: RadiosityError) -> CliError {
    match e {
        RadiosityError::Input(m) => CliError::Input(m),
        RadiosityError::Failure(m) => CliError::Failure(m),
    }
}

/// The options the command line adds to the job's (the job checks its own:
/// [`JobOptions::check`]), before any work.
fn check_options(a: &RadiosityArgs) -> Result<(), CliError> {
    job_options(a).check().map_err(err)?;
    if a.pixel_samples == 0 {
        return Err(CliError::Input("--pixel-samples must be at least 1".into()));
    }
    if a.pixel_samples > 64 {
        return Err(CliError::Input(format!(
            "--pixel-samples {} would trace {} rays per pixel; use at most 64",
            a.pixel_samples,
            a.pixel_samples as u64 * a.pixel_samples as u64
        )));
    }
    irradia_core::image::check_size(a.width, a.height, 12)
        .map_err(|e| CliError::Input(e.to_string()))?;
    output::check_image("-o", &a.output)?;
    if let Some(p) = &a.mesh_out {
        output::check_file("--mesh-out", p, &["ply"])?;
    }
    if let Some(p) = &a.convergence {
        output::check_file("--convergence", p, &["csv"])?;
    }
    Ok(())
}

/// The job's options from the command line (the library's names and defaults).
fn job_options(a: &RadiosityArgs) -> JobOptions {
    JobOptions {
        form_factors: match a.form_factors {
            FormFactorArg::Analytic => Method::Analytic,
            FormFactorArg::Contour => Method::Contour,
            FormFactorArg::Hemisphere => Method::Hemisphere,
            FormFactorArg::Hemicube => Method::Hemicube,
            FormFactorArg::Raycast => Method::RayCast,
            FormFactorArg::Montecarlo => Method::MonteCarlo,
        },
        solver: match a.solver {
            SolverArg::Direct => SolverKind::Direct,
            SolverArg::Jacobi => SolverKind::Jacobi,
            SolverArg::GaussSeidel => SolverKind::GaussSeidel,
            SolverArg::Series => SolverKind::Series,
            SolverArg::Southwell => SolverKind::Southwell,
            SolverArg::Hierarchical => SolverKind::Hierarchical,
        },
        max_element_area: a.max_element_area,
        elements: a.elements,
        element_limit: a.element_limit,
        hemicube_resolution: a.hemicube_resolution,
        hemisphere_resolution: a.hemisphere_resolution,
        rays: a.rays,
        samples: a.samples,
        visibility_samples: a.visibility_samples,
        tolerance: a.tolerance,
        max_iterations: a.max_iterations,
        bf_epsilon: a.bf_epsilon,
        link_rays: a.link_rays,
        adaptive: a.adaptive,
        seed: a.seed,
        compare_solvers: a.convergence.is_some(),
        keep_form_factors: false,
    }
}

pub fn run(mut a: RadiosityArgs) -> Result<(), CliError> {
    check_options(&a)?;
    if a.comm.comm.is_some() && a.solver != SolverArg::Hierarchical {
        return Err(CliError::Input(format!(
            "--comm: only --solver hierarchical runs on several ranks (not {}); \
             drop --comm or add --solver hierarchical",
            a.solver
                .to_possible_value()
                .map_or(String::new(), |v| v.get_name().to_string())
        )));
    }
    // MPI starts before anything is printed; only rank 0 reports and writes.
    let ranks = a.comm.start(None)?;
    a.quiet |= ranks.rank() != 0;
    let source = match (&a.scene, &a.builtin) {
        (Some(_), Some(_)) => {
            return Err(CliError::Input(
                "give either a scene file or --builtin, not both".into(),
            ))
        }
        (None, None) => SceneSource::Default,
        (None, Some(name)) => SceneSource::Builtin(name),
        (Some(path), None) => SceneSource::Scene(Box::new(crate::scene_arg::import_scene(
            path, &a.import, a.quiet,
        )?)),
    };
    let two_pass = a.display == DisplayArg::TwoPass;
    let scene = job::load_scene(source, two_pass, a.closed).map_err(err)?;
    let view = match &scene.scene {
        Some(s) => view_of(s, a.width, a.height)?,
        None => scene.view.view(a.width, a.height),
    };
    let options = job_options(&a);
    let (solver, method) = (options.solver, options.form_factors);
    let display = match a.display {
        DisplayArg::Gouraud => Display::Gouraud,
        DisplayArg::TwoPass => Display::TwoPass {
            samples_per_axis: a.pixel_samples,
        },
    };
    let cfg = options.config(&scene.specs).map_err(err)?;
    if ranks.rank() == 0 {
        for w in &scene.warnings {
            eprintln!("irradia: warning: {w}");
        }
    }
    let phases = Phases(Progress::new("radiosity", a.quiet));
    let report = if a.comm.comm.is_none() {
        pipeline::run(&scene.specs, &cfg, &phases).map_err(err)?
    } else {
        let solve = |mesh: &_, h| ranks.solve_hierarchical(mesh, h);
        match pipeline::run_hierarchical(&scene.specs, &cfg, &phases, solve).map_err(err)? {
            Some(r) => r,
            None => return Ok(()),
        }
    };
    phases.0.finish();
    let t = Instant::now();
    if display == Display::Gouraud && scene.specular.is_some() && !a.quiet {
        eprintln!(
            "irradia: note: the Gouraud image shows mirrors as their black stand-ins and no glass; \
             --display two-pass traces them"
        );
    }
    let img = job::display_image(&report, display, scene.specular.as_ref(), &view).map_err(err)?;
    irradia_core::io::save(&img, &a.output).map_err(|e| CliError::Failure(e.to_string()))?;
    if let Some(p) = &a.mesh_out {
        write_ply(&report.display_mesh(), p).map_err(err)?;
    }
    let display_time = t.elapsed();
    if let Some(p) = &a.convergence {
        let chart = job::write_convergence(p, &report).map_err(err)?;
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
        for line in job::summary_lines(&report, solver, method, display, display_time, &a.output) {
            eprintln!("{line}");
        }
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
