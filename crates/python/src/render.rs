//! `Scene.render`: the library's `irradia_render::render` with the command line's
//! options, run on a thread of its own while the calling thread, the GIL released,
//! waits for it and every 50 ms takes the GIL to run Python's signal handlers
//! (`Python::check_signals`: Ctrl-C) and the progress callback. Signal handlers only
//! run on Python's main thread, so this thread, not the render's workers, checks them;
//! a KeyboardInterrupt (or an exception from the callback) sets the render's cancel
//! flag ([`irradia_render::cancel`]), the workers skip the tiles not yet started, and
//! the exception is raised once the render has stopped.

use crate::errors;
use crate::scene::PyScene;
use irradia_core::Image;
use irradia_render::{Aov, Budget, Progress, ProgressFn, RenderOptions, RenderOutput};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

/// How often the waiting thread looks at signals and progress.
const POLL: Duration = Duration::from_millis(50);

/// The options of one `Scene.render` call.
pub struct RenderArgs {
    pub overrides: irradia_scene::Overrides,
    pub threads: Option<u32>,
    pub aovs: Vec<Aov>,
    pub tile_size: u32,
    pub budget: Budget,
    /// A callable `(done, total)`, or True for a tqdm bar.
    pub progress: Option<PyObject>,
}

/// `aovs=["depth", "normal"]` or `aovs="depth,normal"`, by the command line's names
/// (`object_id` and `ray_depth` also accepted).
pub fn parse_aovs(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Aov>> {
    let Some(obj) = obj else {
        return Ok(Vec::new());
    };
    let names: Vec<String> = if let Ok(s) = obj.downcast::<PyString>() {
        s.to_cow()?
            .split(',')
            .map(|s| s.trim().to_string())
            .collect()
    } else {
        obj.extract()
            .map_err(|_| errors::input("aovs: expected a list of names"))?
    };
    let mut out = Vec::new();
    for n in names.iter().filter(|n| !n.is_empty()) {
        let a: Aov = n.replace('_', "-").parse().map_err(errors::input)?;
        if !out.contains(&a) {
            out.push(a);
        }
    }
    Ok(out)
}

/// The progress callback to call: the user's callable, or for `True` a tqdm bar made
/// by `irradia._progress.bar()` (None when tqdm cannot be imported).
fn progress_callback(py: Python<'_>, p: Option<PyObject>) -> PyResult<Option<PyObject>> {
    let Some(p) = p else {
        return Ok(None);
    };
    let b = p.bind(py);
    if b.is_none() || b.extract::<bool>().ok() == Some(false) {
        return Ok(None);
    }
    if b.extract::<bool>().ok() == Some(true) || b.extract::<String>().is_ok() {
        let bar = py.import("irradia._progress")?.call_method0("bar")?;
        return Ok((!bar.is_none()).then(|| bar.unbind()));
    }
    if !b.is_callable() {
        return Err(errors::input(
            "progress: expected a callable (done, total) or True for a tqdm bar",
        ));
    }
    Ok(Some(p))
}

/// Renders `scene` under `args`; returns the colour array, or a dict with the AOVs.
pub fn render(py: Python<'_>, scene: &mut PyScene, args: RenderArgs) -> PyResult<PyObject> {
    let callback = progress_callback(py, args.progress)?;
    let done = Arc::new(AtomicU64::new(0));
    let total = Arc::new(AtomicU64::new(u64::MAX));
    let cancel = Arc::new(AtomicBool::new(false));
    let progress: Option<ProgressFn> = callback.as_ref().map(|_| {
        let (d, t) = (done.clone(), total.clone());
        let f: ProgressFn = Arc::new(move |p: &Progress| {
            d.store(p.done, Ordering::Relaxed);
            t.store(p.total.unwrap_or(u64::MAX), Ordering::Relaxed);
        });
        f
    });
    let mut options = RenderOptions {
        threads: args.threads.map(|t| t.max(1) as usize),
        tile_size: args.tile_size.max(1),
        aovs: args.aovs.clone(),
        progress,
        cancel: Some(cancel.clone()),
        ..RenderOptions::default()
    };
    let spp_given = args.overrides.spp.is_some();
    let result = scene.with_overrides(&args.overrides, |scene| {
        scene.settings.check_crop().map_err(errors::input)?;
        let path_traced = scene.settings.integrator.is_monte_carlo();
        args.budget.validate(path_traced).map_err(errors::input)?;
        args.budget.apply(&mut options, spp_given);
        let call = |py: Python<'_>, cb: &PyObject| -> PyResult<()> {
            let t = total.load(Ordering::Relaxed);
            let t = (t != u64::MAX).then_some(t);
            cb.call1(py, (done.load(Ordering::Relaxed), t)).map(drop)
        };
        let mut raised: Option<PyErr> = None;
        let out = py.allow_threads(|| {
            std::thread::scope(|s| {
                let (tx, rx) = mpsc::channel();
                let options = &options;
                s.spawn(move || {
                    let _ = tx.send(irradia_render::render(scene, options));
                });
                let mut shown = u64::MAX;
                loop {
                    match rx.recv_timeout(POLL) {
                        Ok(r) => break r,
                        Err(mpsc::RecvTimeoutError::Disconnected) => {
                            break Err(irradia_render::RenderError::Threads(
                                "the render thread stopped without an answer".into(),
                            ))
                        }
                        Err(mpsc::RecvTimeoutError::Timeout) => {}
                    }
                    if raised.is_some() {
                        continue;
                    }
                    Python::with_gil(|py| {
                        let mut r = py.check_signals();
                        let now = done.load(Ordering::Relaxed);
                        if r.is_ok() && now != shown {
                            if let Some(cb) = &callback {
                                shown = now;
                                r = call(py, cb);
                            }
                        }
                        if let Err(e) = r {
                            cancel.store(true, Ordering::Relaxed);
                            raised = Some(e);
                        }
                    });
                }
            })
        });
        if let Some(e) = raised {
            close(py, callback.as_ref());
            return Err(e);
        }
        let out = out.map_err(|e| {
            close(py, callback.as_ref());
            errors::render(e)
        })?;
        if let Some(cb) = &callback {
            call(py, cb)?;
        }
        close(py, callback.as_ref());
        Ok(out)
    })?;
    scene.last = Some(summary(py, &result)?.unbind());
    output(py, result, &args.aovs)
}

/// Closes a tqdm bar (anything with a `close` method).
fn close(py: Python<'_>, cb: Option<&PyObject>) {
    if let Some(cb) = cb {
        if let Ok(c) = cb.bind(py).getattr("close") {
            let _ = c.call0();
        }
    }
}

/// What the render measured, for `Scene.last_render`.
fn summary<'py>(py: Python<'py>, out: &RenderOutput) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("samples", out.samples)?;
    d.set_item("rays", out.stats.total_rays())?;
    d.set_item("seconds", out.elapsed.as_secs_f64())?;
    d.set_item("stop", format!("{:?}", out.stop).to_lowercase())?;
    d.set_item("relative_error", out.relative_error)?;
    d.set_item("statistics", out.stats.to_string())?;
    Ok(d)
}

/// An image as a float32 array of shape (height, width, channels) (channels 3, or 1
/// dropped to (height, width)).
pub fn image_array(py: Python<'_>, image: &Image, channels: usize) -> PyResult<PyObject> {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let mut v = Vec::with_capacity(w * h * channels);
    for p in image.pixels() {
        v.extend_from_slice(&p.to_array()[..channels]);
    }
    let a = PyArray1::from_vec(py, v);
    Ok(if channels == 1 {
        a.reshape([h, w])?.into_any().unbind()
    } else {
        a.reshape([h, w, channels])?.into_any().unbind()
    })
}

/// An id image (object id, ray depth) as an int32 array of shape (height, width).
fn id_array(py: Python<'_>, image: &Image) -> PyResult<PyObject> {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let v: Vec<i32> = image.pixels().iter().map(|p| p.r as i32).collect();
    Ok(PyArray1::from_vec(py, v)
        .reshape([h, w])?
        .into_any()
        .unbind())
}

/// The colour array alone, or a dict of it ("color") and the AOVs by their names:
/// depth (h, w) float32, normal (h, w, 3) float32, object-id and ray-depth (h, w) int32.
fn output(py: Python<'_>, out: RenderOutput, aovs: &[Aov]) -> PyResult<PyObject> {
    let color = image_array(py, &out.image, 3)?;
    if aovs.is_empty() {
        return Ok(color);
    }
    let d = PyDict::new(py);
    d.set_item("color", color)?;
    for (aov, image) in &out.aovs {
        let a = match aov {
            Aov::Depth => image_array(py, image, 1)?,
            Aov::Normal => image_array(py, image, 3)?,
            Aov::ObjectId | Aov::RayDepth => id_array(py, image)?,
        };
        d.set_item(aov.name(), a)?;
    }
    Ok(d.into_any().unbind())
}
