//! Geometry-only timing of the csg workload (../shared/peers/csg.pov): the three CSG
//! objects and the ground plane, 1280x720 primary rays from the POV-Ray camera, and
//! one shadow ray per hit towards the light. Prints rays per second on one thread;
//! no shading, so it bounds how much of the render time CSG intersection takes.
//!
//! `cargo run --release -p irradia-geometry --example csg_rays [repeats] [width]`

use glam::{Affine3A, EulerRot, Quat, Vec3};
use irradia_core::{offset_ray_origin, Ray};
use irradia_geometry::csg::{Csg, CsgOperand};
use irradia_geometry::shapes::{Cuboid, Plane, Quadric, Sphere};
use irradia_geometry::{Accel, Instance, Shape};
use std::sync::Arc;
use std::time::Instant;

fn leaf(s: impl Shape + 'static) -> CsgOperand {
    CsgOperand::shape(Arc::new(s), Affine3A::IDENTITY)
}

fn scene() -> Accel {
    let a = Csg::difference(vec![
        leaf(Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap()),
        leaf(Sphere::new(Vec3::ZERO, 1.3)),
    ])
    .unwrap();
    let a_place = Affine3A::from_translation(Vec3::new(-2.6, 0.9, 0.5))
        * Affine3A::from_rotation_y(30f32.to_radians())
        * Affine3A::from_scale(Vec3::splat(0.9));
    let b = Csg::intersection(vec![
        leaf(
            Quadric::capped_cylinder(Vec3::new(-1.1, 0.0, 0.0), Vec3::new(1.1, 0.0, 0.0), 1.0)
                .unwrap(),
        ),
        leaf(
            Quadric::capped_cylinder(Vec3::new(0.0, -1.1, 0.0), Vec3::new(0.0, 1.1, 0.0), 1.0)
                .unwrap(),
        ),
        leaf(
            Quadric::capped_cylinder(Vec3::new(0.0, 0.0, -1.1), Vec3::new(0.0, 0.0, 1.1), 1.0)
                .unwrap(),
        ),
    ])
    .unwrap();
    let b_place = Affine3A::from_translation(Vec3::new(0.0, 1.1, 1.0))
        * Affine3A::from_quat(Quat::from_euler(
            EulerRot::YXZ,
            35f32.to_radians(),
            25f32.to_radians(),
            0.0,
        ));
    let mut ops = vec![leaf(Sphere::new(Vec3::ZERO, 0.7))];
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        for s in [-0.75, 0.75] {
            ops.push(leaf(Sphere::new(axis * s, 0.45)));
        }
    }
    let c = Csg::union(ops).unwrap();
    let c_place = Affine3A::from_translation(Vec3::new(2.6, 1.2, 0.3));
    Accel::build(vec![
        Instance::untransformed(Arc::new(Plane::new(Vec3::Y, 0.0).unwrap())),
        Instance::new(Arc::new(a), a_place),
        Instance::new(Arc::new(b), b_place),
        Instance::new(Arc::new(c), c_place),
    ])
}

/// User CPU seconds of this process (Linux `/proc/self/stat`, field 14, at 100 ticks
/// per second); `None` elsewhere. On a loaded machine CPU time is steadier than wall.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let after = &stat[stat.rfind(')')? + 2..];
    let utime: f64 = after.split_whitespace().nth(11)?.parse().ok()?;
    Some(utime / 100.0)
}

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let accel = scene();
    let w: u32 = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1280);
    let h = w * 9 / 16;
    let eye = Vec3::new(0.0, 3.2, -7.5);
    let forward = (Vec3::new(0.0, 0.9, 0.0) - eye).normalize();
    let right = Vec3::Y.cross(forward).normalize();
    let up = forward.cross(right);
    let half_w = (55f32.to_radians() / 2.0).tan();
    let half_h = half_w * h as f32 / w as f32;
    let light = Vec3::new(-6.0, 10.0, -8.0);
    let mut best = f64::INFINITY;
    let cpu_start = cpu_seconds();
    let (mut hits, mut shadowed) = (0u64, 0u64);
    for _ in 0..repeats {
        let start = Instant::now();
        hits = 0;
        shadowed = 0;
        for y in 0..h {
            for x in 0..w {
                let u = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * half_w;
                let v = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * half_h;
                let ray = Ray::new(eye, (forward + right * u + up * v).normalize());
                if let Some(sh) = accel.intersect(&ray, f32::INFINITY) {
                    hits += 1;
                    let n = if sh.hit.normal.dot(ray.dir) < 0.0 {
                        sh.hit.normal
                    } else {
                        -sh.hit.normal
                    };
                    let o = offset_ray_origin(sh.hit.point, n, sh.hit.error);
                    let to_light = light - o;
                    if accel.occluded(&Ray::new(o, to_light), 1.0) {
                        shadowed += 1;
                    }
                }
            }
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    let rays = (w * h) as u64 + hits;
    let cpu = match (cpu_start, cpu_seconds()) {
        (Some(a), Some(b)) => format!(", {:.3} s of CPU per pass", (b - a) / repeats as f64),
        _ => String::new(),
    };
    println!(
        "csg geometry: {} primary + {} shadow rays ({} shadowed) in {:.3} s best of {repeats} on 1 thread: {:.2} Mrays/s{cpu}",
        w * h,
        hits,
        shadowed,
        best,
        rays as f64 / best / 1e6
    );
}
