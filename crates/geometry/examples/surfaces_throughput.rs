//! Primary-ray throughput of the curved surfaces (torus, Bézier teapot, implicit surfaces
//! with both root finders, parametric surface): a 640x480 pinhole view of each shape,
//! timed per shape, with the thread count given on the command line (rayon).
//!
//! `cargo run --release -p irradia-geometry --example surfaces_throughput -- [THREADS] [RUNS]`
//! prints one line per shape: the median Mrays/s over RUNS runs (default 5) and the hit
//! count (identical across runs and thread counts). `bench/surfaces/run.sh` runs it with
//! 1 and 2 threads.

use irradia_core::{Aabb, Ray, Vec3};
use irradia_geometry::shapes::{BezierSurface, ImplicitSurface, ParametricSurface, Torus};
use irradia_geometry::Shape;
use rayon::prelude::*;
use std::time::Instant;

fn camera_rays(eye: Vec3, at: Vec3, w: u32, h: u32) -> Vec<Ray> {
    let fwd = (at - eye).normalize();
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    let tan = (45f32.to_radians() * 0.5).tan();
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let sx = ((x as f32 + 0.5) / w as f32 * 2.0 - 1.0) * tan * w as f32 / h as f32;
            let sy = (1.0 - (y as f32 + 0.5) / h as f32 * 2.0) * tan;
            Ray::new(eye, fwd + right * sx + up * sy)
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let threads: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let runs: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let cube = |h: f32| Aabb::new(Vec3::splat(-h), Vec3::splat(h));
    let blob = "(x^2+y^2+z^2)^2 - 2*(x^2+y^2+z^2) + 1.2*sin(4*x)*sin(4*y)*sin(4*z) + 0.6";
    let setup = std::time::Instant::now();
    let shapes: Vec<(&str, Box<dyn Shape>, Vec3, Vec3)> = vec![
        (
            "torus",
            Box::new(Torus::new(1.0, 0.35)),
            Vec3::new(0.0, 2.0, 3.0),
            Vec3::ZERO,
        ),
        (
            "teapot (level 8)",
            Box::new(BezierSurface::teapot(8).expect("teapot")),
            Vec3::new(4.0, 5.0, 7.0),
            Vec3::new(0.2, 1.3, 0.0),
        ),
        (
            "implicit sphere, interval",
            Box::new(ImplicitSurface::parse("x^2+y^2+z^2-1", cube(1.5)).expect("implicit")),
            Vec3::new(0.0, 1.0, 3.5),
            Vec3::ZERO,
        ),
        (
            "implicit sphere, Lipschitz",
            Box::new(
                ImplicitSurface::parse("x^2+y^2+z^2-1", cube(1.5))
                    .and_then(|s| s.with_lipschitz(5.2))
                    .expect("implicit"),
            ),
            Vec3::new(0.0, 1.0, 3.5),
            Vec3::ZERO,
        ),
        (
            "implicit blob, interval",
            Box::new(ImplicitSurface::parse(blob, cube(1.6)).expect("implicit")),
            Vec3::new(2.5, 2.5, 4.0),
            Vec3::ZERO,
        ),
        (
            "parametric Moebius (96x16)",
            Box::new(
                ParametricSurface::parse(
                    [
                        "(1 + 0.5*v*cos(u/2))*cos(u)",
                        "0.5*v*sin(u/2)",
                        "(1 + 0.5*v*cos(u/2))*sin(u)",
                    ],
                    (0.0, 2.0 * std::f64::consts::PI),
                    (-1.0, 1.0),
                    (96, 16),
                )
                .expect("parametric"),
            ),
            Vec3::new(0.0, 2.0, 3.5),
            Vec3::ZERO,
        ),
    ];
    println!(
        "setup (teapot and parametric tessellation + BVH): {:.1} ms",
        setup.elapsed().as_secs_f64() * 1e3
    );
    println!("threads {threads}, runs {runs}, 640x480 primary rays per run");
    for (name, shape, eye, at) in &shapes {
        let rays = camera_rays(*eye, *at, 640, 480);
        let mut rates = Vec::new();
        let mut hits = 0;
        for _ in 0..runs {
            let start = Instant::now();
            hits = pool.install(|| {
                rays.par_chunks(4096)
                    .map(|c| {
                        c.iter()
                            .filter(|r| shape.intersect(r, f32::INFINITY).is_some())
                            .count()
                    })
                    .sum::<usize>()
            });
            rates.push(rays.len() as f64 / start.elapsed().as_secs_f64() / 1e6);
        }
        rates.sort_by(f64::total_cmp);
        println!(
            "{name:<30} {:>8.3} Mrays/s (median of {runs})   hits {hits}",
            rates[rates.len() / 2]
        );
    }
}
