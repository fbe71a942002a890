//! The rasterizer benchmark of docs/benchmarks/raster.md (driven by bench/raster/run.sh).
//!
//! ```text
//! raster_bench write random|gyroid FILE      write the workload (mesh + view + light)
//! raster_bench time FILE FRAMES THREADS [PNG] render 1 + FRAMES frames, print the
//!                                             times of the last FRAMES (clear + render_mesh)
//! ```
//! With a PNG path, `time` also prints the pixels per input triangle and, when
//! `RASTER_BENCH_STATS` is set, a histogram of the screen triangles by the pixel
//! centres in their bounding box (capped at 9) and the centres they cover.
//! The file is read by bench/raster/llvmpipe.py as well, so both renderers draw the
//! same triangles from the same view. Layout (little-endian): b"IRRT", u32 width,
//! u32 height, f32 eye[3], target[3], up[3], fovy_degrees, near, far,
//! light_direction[3] (travel direction), light[3], ambient[3], diffuse[3],
//! u32 vertex count, u32 triangle count, f32 positions[3n], f32 normals[3n],
//! u32 indices[3m].

use glam::Vec3;
use irradia_core::Rgb;
use irradia_geometry::generators::gyroid::{gyroid_mesh, BENCHMARK_GRID};
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_raster::{
    for_each_fragment, ColorFormat, Framebuffer, Lights, Material, Mesh, Pipeline, RasterLight,
    Rect, Shading, ViewParams,
};
use std::io::{Read, Write};
use std::time::Instant;

struct Workload {
    width: u32,
    height: u32,
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fovy: f32,
    near: f32,
    far: f32,
    light_dir: Vec3,
    light: Vec3,
    ambient: Vec3,
    diffuse: Vec3,
    mesh: Mesh,
}

fn make(kind: &str) -> Workload {
    let (mesh, eye) = match kind {
        "random" => {
            // 1M triangles in a box that fills a 16:9 screen; the area is set so a
            // triangle covers about 23 pixels on average (printed by `time`).
            let mut spec = RandomTriangles::new(1_000_000, SizeDistribution::Constant(9.5e-4), 1);
            spec.bounds =
                irradia_core::Aabb::new(Vec3::new(-2.3, -1.3, -1.0), Vec3::new(2.3, 1.3, 1.0));
            let m = random_triangles(&spec);
            (Mesh::new(m.positions, m.indices), Vec3::new(0.0, 0.0, 4.2))
        }
        "gyroid" => {
            let m = gyroid_mesh(BENCHMARK_GRID);
            (Mesh::new(m.positions, m.indices), Vec3::new(1.5, 1.1, 1.9))
        }
        other => panic!("unknown workload {other} (random | gyroid)"),
    };
    let mut mesh = mesh;
    mesh.compute_vertex_normals();
    Workload {
        width: 1280,
        height: 720,
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        fovy: 45.0,
        near: 0.1,
        far: 20.0,
        light_dir: Vec3::new(-0.4, -0.6, -0.7).normalize(),
        light: Vec3::splat(0.9),
        ambient: Vec3::splat(0.15),
        diffuse: Vec3::new(0.9, 0.75, 0.5),
        mesh,
    }
}

fn put(out: &mut Vec<u8>, v: &[f32]) {
    for f in v {
        out.extend_from_slice(&f.to_le_bytes());
    }
}

fn write(w: &Workload, path: &str) {
    let mut b = b"IRRT".to_vec();
    b.extend_from_slice(&w.width.to_le_bytes());
    b.extend_from_slice(&w.height.to_le_bytes());
    for v in [w.eye, w.target, w.up] {
        put(&mut b, &v.to_array());
    }
    put(&mut b, &[w.fovy, w.near, w.far]);
    for v in [w.light_dir, w.light, w.ambient, w.diffuse] {
        put(&mut b, &v.to_array());
    }
    b.extend_from_slice(&(w.mesh.positions.len() as u32).to_le_bytes());
    b.extend_from_slice(&(w.mesh.indices.len() as u32).to_le_bytes());
    for p in &w.mesh.positions {
        put(&mut b, &p.to_array());
    }
    for n in &w.mesh.normals {
        put(&mut b, &n.to_array());
    }
    for t in &w.mesh.indices {
        for i in t {
            b.extend_from_slice(&i.to_le_bytes());
        }
    }
    std::fs::File::create(path)
        .and_then(|mut f| f.write_all(&b))
        .expect("write workload");
}

fn read(path: &str) -> Workload {
    let mut b = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut b))
        .expect("read workload");
    assert_eq!(&b[..4], b"IRRT", "{path}: not a raster_bench workload");
    let mut at = 4;
    let mut u = || {
        let v = u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        at += 4;
        v
    };
    let width = u();
    let height = u();
    let mut fl = [0f32; 24];
    for f in &mut fl {
        *f = f32::from_bits(u());
    }
    let v3 = |i: usize| Vec3::new(fl[i], fl[i + 1], fl[i + 2]);
    let nv = u() as usize;
    let nt = u() as usize;
    let mut vecs = |n: usize| {
        (0..n)
            .map(|_| {
                Vec3::new(
                    f32::from_bits(u()),
                    f32::from_bits(u()),
                    f32::from_bits(u()),
                )
            })
            .collect::<Vec<_>>()
    };
    let positions = vecs(nv);
    let normals = vecs(nv);
    let indices = (0..nt).map(|_| [u(), u(), u()]).collect();
    let mut mesh = Mesh::new(positions, indices);
    mesh.normals = normals;
    Workload {
        width,
        height,
        eye: v3(0),
        target: v3(3),
        up: v3(6),
        fovy: fl[9],
        near: fl[10],
        far: fl[11],
        light_dir: v3(12),
        light: v3(15),
        ambient: v3(18),
        diffuse: v3(21),
        mesh,
    }
}

fn pipeline(w: &Workload) -> Pipeline {
    let mut p = Pipeline::new(w.width, w.height);
    p.view = ViewParams::look_at_perspective(
        w.eye,
        w.target,
        w.up,
        w.fovy,
        w.width as f32 / w.height as f32,
        w.near,
        w.far,
    );
    let rgb = |v: Vec3| Rgb::new(v.x, v.y, v.z);
    p.lights = Lights {
        ambient: rgb(w.ambient),
        lights: vec![RasterLight::Directional {
            direction: w.light_dir,
            color: rgb(w.light),
        }],
    };
    p.material = Material {
        diffuse: rgb(w.diffuse),
        specular: Rgb::BLACK,
        shininess: 1.0,
        two_sided: true,
        ..Material::default()
    };
    p.shading = Shading::Gouraud;
    p
}

fn time(path: &str, frames: usize, threads: usize, png: Option<&str>) {
    let w = read(path);
    let p = pipeline(&w);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let mut fb = Framebuffer::new(w.width, w.height, ColorFormat::Rgba8).expect("framebuffer");
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    pool.install(|| {
        // One untimed warm-up frame (first-touch page faults), then `frames` timed.
        for frame in 0..=frames {
            let t0 = Instant::now();
            let c0 = process_cpu_s();
            fb.clear([0.0, 0.0, 0.0, 1.0]);
            if std::env::var_os("RASTER_BENCH_SPLIT").is_some() {
                let tris = p.transform_mesh(&w.mesh).expect("mesh");
                let t1 = Instant::now();
                p.rasterize(&tris, &mut fb, None).expect("raster");
                eprintln!(
                    "geometry {:.3} s, raster {:.3} s",
                    (t1 - t0).as_secs_f64(),
                    t1.elapsed().as_secs_f64()
                );
            } else {
                p.render_mesh(&w.mesh, &mut fb).expect("render");
            }
            if frame > 0 {
                times.push(t0.elapsed().as_secs_f64());
                cpu.push(process_cpu_s() - c0);
            }
        }
    });
    if let Some(png) = png {
        image::save_buffer(
            png,
            &fb.to_rgba8_bytes(),
            w.width,
            w.height,
            image::ColorType::Rgba8,
        )
        .expect("write png");
        // Mean pixels per drawn triangle (coverage without the depth test).
        let tris = p.transform_mesh(&w.mesh).expect("mesh");
        let screen = Rect::full(w.width, w.height);
        let mut fragments = 0u64;
        let mut hist = std::collections::BTreeMap::<(i64, u64), u64>::new();
        for t in &tris {
            let mut n = 0u64;
            for_each_fragment(t, &screen, |_, _, _| n += 1);
            fragments += n;
            if std::env::var_os("RASTER_BENCH_STATS").is_some() {
                let (x0, x1, y0, y1) = irradia_raster::rasterizer::row_range(t);
                let bb = ((x1 - x0 + 1).max(0) * (y1 - y0 + 1).max(0)).min(9);
                *hist.entry((bb, n.min(9))).or_default() += 1;
            }
        }
        for ((bb, n), c) in &hist {
            eprintln!("bbox {bb} covered {n}: {c}");
        }
        eprintln!(
            "{} triangles, {} after clipping and culling, {:.1} pixels per input triangle",
            w.mesh.indices.len(),
            tris.len(),
            fragments as f64 / w.mesh.indices.len() as f64
        );
    }
    let mut sorted = times.clone();
    sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
    cpu.sort_by(|a, b| a.partial_cmp(b).unwrap());
    println!(
        "{{\"renderer\":\"irradia\",\"threads\":{threads},\"frames\":{frames},\"median_s\":{:.5},\"min_s\":{:.5},\"cpu_median_s\":{:.5},\"times\":{:?}}}",
        sorted[sorted.len() / 2],
        sorted[0],
        cpu[cpu.len() / 2],
        times
    );
}

/// The CPU time of the whole process so far (all threads), in seconds: per-frame CPU
/// time is steadier than wall time on a machine shared with other work (it includes
/// the pool's threads spinning while they wait for work).
fn process_cpu_s() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, t: *mut Timespec) -> i32;
    }
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: `t` is a valid timespec for the C library to fill.
    if unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut t) } != 0 {
        return f64::NAN;
    }
    t.sec as f64 + t.nsec as f64 * 1e-9
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    match args.get(1).map(String::as_str) {
        Some("write") if args.len() == 4 => write(&make(&args[2]), &args[3]),
        Some("time") if args.len() >= 5 => time(
            &args[2],
            args[3].parse().expect("FRAMES"),
            args[4].parse().expect("THREADS"),
            args.get(5).map(String::as_str),
        ),
        _ => {
            eprintln!("usage: raster_bench write random|gyroid FILE | raster_bench time FILE FRAMES THREADS [PNG]");
            std::process::exit(2);
        }
    }
}
