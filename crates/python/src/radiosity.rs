//! Radiosity from Python: the lecture's closed-form form factors
//! (`irradia.form_factor`, as `irradia formfactor`) and a whole radiosity solve
//! (`irradia.radiosity`, as `irradia radiosity`: the same scenes, option names,
//! defaults and messages, through the library's `JobOptions` and `pipeline::run`),
//! returning per-element radiosity, areas, the residual history and, when asked, the
//! form-factor matrix as numpy arrays.

use crate::errors;
use crate::scene::PyScene;
use irradia_radiosity::formfactor::analytic::{lookup, CASES};
use irradia_radiosity::formfactor::Method;
use irradia_radiosity::job::{self, SceneSource};
use irradia_radiosity::options::JobOptions;
use irradia_radiosity::pipeline::{self, NoProgress};
use irradia_radiosity::solver::SolverKind;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A closed form of the lecture's catalogue ("Form Factor Examples 1-3") with its
/// parameters by name: `form_factor("perpendicular-rectangles", h=1, l=1, w=1)`.
#[pyfunction]
#[pyo3(signature = (case, **params))]
pub fn form_factor(case: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<f64> {
    let case = lookup(case).map_err(errors::input)?;
    let mut given = Vec::new();
    if let Some(params) = params {
        for (k, v) in params.iter() {
            let name: String = k.extract()?;
            let x: f64 = v
                .extract()
                .map_err(|_| errors::input(format!("--{name} {v}: not a number")))?;
            given.push((name, x));
        }
    }
    case.eval_named(&given).map_err(errors::input)
}

/// The catalogue: name, geometry and parameters (name -> meaning) of every case.
#[pyfunction]
pub fn form_factor_cases(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for c in CASES {
        let d = PyDict::new(py);
        d.set_item("name", c.name)?;
        d.set_item("geometry", c.geometry)?;
        let p = PyDict::new(py);
        for (n, what) in c.params {
            p.set_item(*n, *what)?;
        }
        d.set_item("params", p)?;
        list.append(d)?;
    }
    Ok(list)
}

fn method_by_name(s: &str) -> PyResult<Method> {
    Method::parse(s).ok_or_else(|| {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        errors::input(format!(
            "form_factors: unknown method '{s}' (use {})",
            names.join(", ")
        ))
    })
}

fn solver_by_name(s: &str) -> PyResult<SolverKind> {
    SolverKind::parse(s).ok_or_else(|| {
        let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
        errors::input(format!(
            "solver: unknown solver '{s}' (use {})",
            names.join(", ")
        ))
    })
}

fn f64_array(py: Python<'_>, v: Vec<f64>, shape: &[usize]) -> PyResult<PyObject> {
    Ok(PyArray1::from_vec(py, v)
        .reshape(shape.to_vec())?
        .into_any()
        .unbind())
}

/// Solves a scene by radiosity; see the stubs for the arguments.
#[pyfunction]
#[pyo3(signature = (scene=None, *, builtin=None, form_factors="hemicube", solver="gauss-seidel",
    max_element_area=None, elements=1000, element_limit=2_000_000, hemicube_resolution=128,
    hemisphere_resolution=64, rays=16, samples=16, visibility_samples=4, tolerance=1e-6,
    max_iterations=10_000, bf_epsilon=1e-4, link_rays=4, adaptive=0, seed=1, closed=false,
    compare_solvers=false, return_form_factors=false))]
#[allow(clippy::too_many_arguments)]
pub fn radiosity(
    py: Python<'_>,
    scene: Option<&Bound<'_, PyAny>>,
    builtin: Option<&str>,
    form_factors: &str,
    solver: &str,
    max_element_area: Option<f64>,
    elements: usize,
    element_limit: usize,
    hemicube_resolution: usize,
    hemisphere_resolution: usize,
    rays: usize,
    samples: usize,
    visibility_samples: usize,
    tolerance: f64,
    max_iterations: usize,
    bf_epsilon: f64,
    link_rays: usize,
    adaptive: usize,
    seed: u64,
    closed: bool,
    compare_solvers: bool,
    return_form_factors: bool,
) -> PyResult<Py<PyDict>> {
    let options = JobOptions {
        form_factors: method_by_name(form_factors)?,
        solver: solver_by_name(solver)?,
        max_element_area,
        elements,
        element_limit,
        hemicube_resolution,
        hemisphere_resolution,
        rays,
        samples,
        visibility_samples,
        tolerance,
        max_iterations,
        bf_epsilon,
        link_rays,
        adaptive,
        seed,
        compare_solvers,
        keep_form_factors: return_form_factors,
    };
    options.check().map_err(errors::radiosity)?;
    // The patches: a Scene object, a scene file, a built-in, or the measured Cornell box.
    let (specs, warnings) = match (scene, builtin) {
        (Some(_), Some(_)) => {
            return Err(errors::input("give either a scene or builtin, not both"))
        }
        (Some(s), None) => {
            if let Ok(s) = s.downcast::<PyScene>() {
                let s = s.borrow();
                job::patches_of(&s.scene, closed).map_err(errors::radiosity)?
            } else {
                let path: PathBuf = s
                    .extract()
                    .map_err(|_| errors::input("scene: expected an irradia.Scene or a path"))?;
                irradia_import::check_path(&path).map_err(errors::scene)?;
                let (scene, _) =
                    irradia_import::load(&path, &Default::default()).map_err(errors::scene)?;
                job::patches_of(&scene, closed).map_err(errors::radiosity)?
            }
        }
        (None, b) => {
            let source = b.map_or(SceneSource::Default, SceneSource::Builtin);
            let j = job::load_scene(source, false, closed).map_err(errors::radiosity)?;
            (j.specs, j.warnings)
        }
    };
    let cfg = options.config(&specs).map_err(errors::radiosity)?;
    let report = py
        .allow_threads(|| pipeline::run(&specs, &cfg, &NoProgress))
        .map_err(errors::radiosity)?;

    let d = PyDict::new(py);
    let n = report.mesh.elements.len();
    let b: Vec<f64> = report.solution.b.iter().flatten().copied().collect();
    d.set_item("radiosity", f64_array(py, b, &[n, 3])?)?;
    let shown: Vec<f64> = report
        .display_radiosity()
        .iter()
        .flatten()
        .copied()
        .collect();
    d.set_item("display_radiosity", f64_array(py, shown, &[n, 3])?)?;
    let area: Vec<f64> = report.mesh.elements.iter().map(|e| e.area).collect();
    d.set_item("area", f64_array(py, area, &[n])?)?;
    let patch: Vec<u32> = report
        .mesh
        .elements
        .iter()
        .map(|e| report.mesh.patches[e.patch as usize].source)
        .collect();
    d.set_item("surface", PyArray1::from_vec(py, patch))?;
    let c: Vec<f64> = report
        .mesh
        .elements
        .iter()
        .flat_map(|e| e.centroid.to_array())
        .collect();
    d.set_item("centroid", f64_array(py, c, &[n, 3])?)?;
    let h = report.solution.history.clone();
    let hn = h.len();
    d.set_item("residuals", f64_array(py, h, &[hn])?)?;
    d.set_item("residual", report.solution.residual)?;
    let hist = PyDict::new(py);
    for (name, h) in &report.histories {
        let k = h.len();
        hist.set_item(name, f64_array(py, h.clone(), &[k])?)?;
    }
    d.set_item("histories", hist)?;
    if let Some(ff) = &report.form_factors {
        d.set_item("form_factors", f64_array(py, ff.f.clone(), &[ff.n, ff.n])?)?;
    }
    if let Some(diag) = &report.diagnostics {
        d.set_item("diagnostics", diag.to_string())?;
    }
    let t = PyDict::new(py);
    for (name, dt) in &report.timings {
        t.set_item(name, dt.as_secs_f64())?;
    }
    d.set_item("timings", t)?;
    d.set_item("notes", report.notes.clone())?;
    d.set_item("warnings", warnings)?;
    Ok(d.unbind())
}
