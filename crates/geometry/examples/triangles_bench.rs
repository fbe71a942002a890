//! The triangles benchmark of PEERS.md (run by bench/triangles/run.py).
//!
//! `triangles_bench write DIR [GRID]`: meshes the gyroid and writes it and the two ray
//! sets as raw little-endian arrays, so Embree (bench/triangles/embree_bench.py) traces
//! exactly the same rays:
//!   vertices.f32 (N x 3), indices.u32 (M x 3),
//!   primary_org.f32, primary_dir.f32 (1280 * 720 x 3), incoherent_org.f32, incoherent_dir.f32 (1e6 x 3).
//! `triangles_bench pair DIR [ROUNDS [SET]]`: single-ray against batched tracing,
//! paired in one process on one thread (CPU seconds; see `pair`), of both ray sets
//! or only SET (primary or incoherent).
//! `triangles_bench run DIR`: loads them, builds the mesh BVH, traces both sets once
//! (closest hit, in chunks of 256 rays through `TriangleMesh::intersect_triangles`,
//! which traces coherent groups of eight as packets; TRIANGLES_SINGLE=1 traces each
//! ray alone) on the rayon pool (RAYON_NUM_THREADS threads), writes the hit
//! distances (`*_t_irradia.f32`, +inf for a miss) and prints one JSON line of timings.

use glam::Vec3;
use irradia_core::{Ray, Rng};
use irradia_geometry::bvh::Bvh;
use irradia_geometry::generators::{gyroid::BENCHMARK_GRID, gyroid_mesh};
use irradia_geometry::TriangleMesh;
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

const WIDTH: usize = 1280;
const HEIGHT: usize = 720;
const INCOHERENT: usize = 1_000_000;

fn write_f32(path: &Path, v: &[f32]) {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}
fn write_u32(path: &Path, v: &[u32]) {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}
fn read_f32(path: &Path) -> Vec<f32> {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}
fn read_u32(path: &Path) -> Vec<u32> {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    b.chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}
fn vecs(v: &[f32]) -> Vec<Vec3> {
    v.chunks_exact(3).map(Vec3::from_slice).collect()
}
fn flat(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Pinhole at (1.5, 1.1, 1.9) looking at the origin, +y up, vertical fov 45°, one
/// ray through each pixel centre, rows top to bottom.
fn primary_rays() -> (Vec<Vec3>, Vec<Vec3>) {
    let eye = Vec3::new(1.5, 1.1, 1.9);
    let forward = (-eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let tan = (45f32.to_radians() * 0.5).tan();
    let aspect = WIDTH as f32 / HEIGHT as f32;
    let mut dirs = Vec::with_capacity(WIDTH * HEIGHT);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let sx = (2.0 * (x as f32 + 0.5) / WIDTH as f32 - 1.0) * tan * aspect;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / HEIGHT as f32) * tan;
            dirs.push((forward + sx * right + sy * up).normalize());
        }
    }
    (vec![eye; WIDTH * HEIGHT], dirs)
}

/// Origins uniform in [-1, 1]^3, directions uniform on the sphere.
fn incoherent_rays() -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = Rng::new(2026, 11);
    let mut org = Vec::with_capacity(INCOHERENT);
    let mut dir = Vec::with_capacity(INCOHERENT);
    for _ in 0..INCOHERENT {
        org.push(Vec3::new(
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
        ));
        let z = 1.0 - 2.0 * rng.next_f32();
        let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        dir.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
    }
    (org, dir)
}

/// CPU seconds used by this process so far (user + system, from /proc/self/stat):
/// on a loaded machine this shows the work done where wall time cannot.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

/// Kept out of line so a profiler can select it (`valgrind --tool=callgrind
/// --toggle-collect='*trace*'`).
#[inline(never)]
fn trace(mesh: &TriangleMesh, org: &[Vec3], dir: &[Vec3]) -> (Vec<f32>, f64) {
    // TRIANGLES_SINGLE=1 traces every ray alone (`intersect_triangle`), the path
    // before packets, for paired comparisons with one binary.
    let single = std::env::var("TRIANGLES_SINGLE").is_ok_and(|v| v == "1");
    let mut t = vec![f32::INFINITY; org.len()];
    let start = Instant::now();
    t.par_chunks_mut(256).enumerate().for_each(|(c, out)| {
        let base = c * 256;
        if single {
            for (k, o) in out.iter_mut().enumerate() {
                let ray = Ray::new(org[base + k], dir[base + k]);
                if let Some((_, h)) = mesh.intersect_triangle(&ray, f32::INFINITY) {
                    *o = h.t;
                }
            }
            return;
        }
        // Batches: coherent groups of eight consecutive rays go through the packet
        // traversal, the others one by one (`TriangleMesh::intersect_triangles`).
        let rays: Vec<Ray> = (0..out.len())
            .map(|k| Ray::new(org[base + k], dir[base + k]))
            .collect();
        let mut hits = vec![None; out.len()];
        mesh.intersect_triangles(&rays, f32::INFINITY, &mut hits);
        for (o, h) in out.iter_mut().zip(&hits) {
            if let Some((_, h)) = h {
                *o = h.t;
            }
        }
    });
    (t, start.elapsed().as_secs_f64())
}

/// Every ray of `org`/`dir` traced alone (`single`) or in batches
/// (`intersect_triangles`), on the calling thread; the number of hits.
fn trace_once(mesh: &TriangleMesh, org: &[Vec3], dir: &[Vec3], single: bool) -> usize {
    let mut hits = 0;
    let mut rays = Vec::with_capacity(256);
    let mut out = vec![None; 256];
    for (o, d) in org.chunks(256).zip(dir.chunks(256)) {
        if single {
            for (o, d) in o.iter().zip(d) {
                hits += mesh
                    .intersect_triangle(&Ray::new(*o, *d), f32::INFINITY)
                    .is_some() as usize;
            }
        } else {
            rays.clear();
            rays.extend(o.iter().zip(d).map(|(o, d)| Ray::new(*o, *d)));
            let out = &mut out[..rays.len()];
            mesh.intersect_triangles(&rays, f32::INFINITY, out);
            hits += out.iter().filter(|h| h.is_some()).count();
        }
    }
    hits
}

/// `pair DIR ROUNDS`: builds the mesh once, then traces each ray set ROUNDS times on
/// one thread, single-ray and batched alternately (A B A B ...), and prints the CPU
/// seconds of each path summed over the rounds and their ratio: a paired comparison
/// of the two traversals in one process, which a loaded machine disturbs least.
fn pair(dir: &Path, rounds: usize, only: Option<&str>) {
    let positions = vecs(&read_f32(&dir.join("vertices.f32")));
    let indices: Vec<[u32; 3]> = read_u32(&dir.join("indices.u32"))
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let mesh = TriangleMesh::new(positions, indices, None, None).expect("valid mesh");
    for set in ["primary", "incoherent"] {
        if only.is_some_and(|o| o != set) {
            continue;
        }
        let o = vecs(&read_f32(&dir.join(format!("{set}_org.f32"))));
        let d = vecs(&read_f32(&dir.join(format!("{set}_dir.f32"))));
        let (mut single_s, mut batch_s) = (0.0, 0.0);
        let mut hits = (0, 0);
        for _ in 0..rounds {
            let c0 = cpu_seconds();
            hits.0 = trace_once(&mesh, &o, &d, true);
            let c1 = cpu_seconds();
            hits.1 = trace_once(&mesh, &o, &d, false);
            let c2 = cpu_seconds();
            single_s += c1 - c0;
            batch_s += c2 - c1;
        }
        assert_eq!(hits.0, hits.1, "{set}: both paths must hit the same rays");
        println!(
            "{{\"set\": \"{set}\", \"rounds\": {rounds}, \"rays\": {}, \"single_cpu_s\": {single_s:.3}, \"batch_cpu_s\": {batch_s:.3}, \"batch_over_single\": {:.3}, \"single_mrays_cpu\": {:.3}, \"batch_mrays_cpu\": {:.3}}}",
            o.len(),
            batch_s / single_s,
            (o.len() * rounds) as f64 / single_s / 1e6,
            (o.len() * rounds) as f64 / batch_s / 1e6,
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: triangles_bench write DIR [GRID] | triangles_bench run DIR | triangles_bench memory DIR | triangles_bench pair DIR [ROUNDS [primary|incoherent]]";
    if args.len() < 3 {
        eprintln!("{usage}");
        std::process::exit(2);
    }
    let dir = Path::new(&args[2]);
    match args[1].as_str() {
        "write" => {
            std::fs::create_dir_all(dir).unwrap();
            let grid = args
                .get(3)
                .map(|s| s.parse().expect("GRID must be an integer"))
                .unwrap_or(BENCHMARK_GRID);
            let t = Instant::now();
            let m = gyroid_mesh(grid);
            eprintln!(
                "gyroid {grid}^3: {} vertices, {} triangles ({:.2} s)",
                m.positions.len(),
                m.indices.len(),
                t.elapsed().as_secs_f64()
            );
            write_f32(&dir.join("vertices.f32"), &flat(&m.positions));
            let idx: Vec<u32> = m.indices.iter().flatten().copied().collect();
            write_u32(&dir.join("indices.u32"), &idx);
            let (o, d) = primary_rays();
            write_f32(&dir.join("primary_org.f32"), &flat(&o));
            write_f32(&dir.join("primary_dir.f32"), &flat(&d));
            let (o, d) = incoherent_rays();
            write_f32(&dir.join("incoherent_org.f32"), &flat(&o));
            write_f32(&dir.join("incoherent_dir.f32"), &flat(&d));
        }
        "pair" => {
            let rounds = args
                .get(3)
                .map(|s| s.parse().expect("ROUNDS must be an integer"))
                .unwrap_or(10);
            pair(dir, rounds, args.get(4).map(String::as_str));
        }
        "memory" => {
            // Peak memory of the build above the loaded arrays, in one process: read the
            // arrays (their parse buffers freed), reset the peak resident size (Linux:
            // `5` to /proc/self/clear_refs), note the resident size, build the mesh (its
            // BVH, triangle packets and normals), and report how far the peak rose.
            let positions = vecs(&read_f32(&dir.join("vertices.f32")));
            let indices: Vec<[u32; 3]> = read_u32(&dir.join("indices.u32"))
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            let n = indices.len();
            let status_kib = |field: &str| {
                std::fs::read_to_string("/proc/self/status")
                    .unwrap_or_default()
                    .lines()
                    .find(|l| l.starts_with(field))
                    .and_then(|l| l.split_whitespace().nth(1))
                    .and_then(|k| k.parse::<u64>().ok())
                    .unwrap_or(0)
            };
            std::fs::write("/proc/self/clear_refs", "5").expect("reset the peak resident size");
            let base = status_kib("VmRSS:");
            let mesh = TriangleMesh::new(positions, indices, None, None).expect("valid mesh");
            std::hint::black_box(&mesh);
            let peak = status_kib("VmHWM:");
            println!(
                "{{\"renderer\": \"irradia\", \"triangles\": {n}, \"base_kib\": {base}, \"peak_kib\": {peak}, \"build_kib\": {}, \"bytes_per_triangle\": {:.1}}}",
                peak - base,
                (peak - base) as f64 * 1024.0 / n as f64
            );
        }
        "run" => {
            let positions = vecs(&read_f32(&dir.join("vertices.f32")));
            let indices: Vec<[u32; 3]> = read_u32(&dir.join("indices.u32"))
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            let n_tris = indices.len();
            // BVH build alone (boxes -> nodes), then the whole mesh construction
            // (validation, normals, boxes, BVH, triangles copied into leaf order).
            let boxes: Vec<irradia_core::Aabb> = indices
                .par_iter()
                .map(|t| irradia_core::Aabb::from_points(t.map(|i| positions[i as usize])))
                .collect();
            // TRIANGLES_RAYS=N traces only the first N rays of each set (profiling).
            let limit: usize = std::env::var("TRIANGLES_RAYS")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(usize::MAX);
            // (and skips the separate BVH build, whose statistics it then leaves out).
            let boxes = if limit == usize::MAX {
                &boxes[..]
            } else {
                &boxes[..1]
            };
            let t0 = Instant::now();
            let c0 = cpu_seconds();
            let bvh = Bvh::build_blocked(boxes, 8);
            let bvh_s = t0.elapsed().as_secs_f64();
            let bvh_cpu = cpu_seconds() - c0;
            let stats = bvh.stats();
            drop(bvh);
            let t0 = Instant::now();
            let c_mesh = cpu_seconds();
            let mesh = TriangleMesh::new(positions, indices, None, None).expect("valid mesh");
            let mesh_s = t0.elapsed().as_secs_f64();
            let mesh_cpu = cpu_seconds() - c_mesh;
            let load = |name: &str| {
                let mut v = vecs(&read_f32(&dir.join(name)));
                v.truncate(limit);
                v
            };
            let (po, pd) = (load("primary_org.f32"), load("primary_dir.f32"));
            let (io, id) = (load("incoherent_org.f32"), load("incoherent_dir.f32"));
            let c0 = cpu_seconds();
            let (pt, p_s) = trace(&mesh, &po, &pd);
            let c1 = cpu_seconds();
            let (it, i_s) = trace(&mesh, &io, &id);
            let c2 = cpu_seconds();
            eprintln!(
                "cpu seconds: bvh build {bvh_cpu:.2}, primary {:.2}, incoherent {:.2}",
                c1 - c0,
                c2 - c1
            );
            if limit == usize::MAX {
                write_f32(&dir.join("primary_t_irradia.f32"), &pt);
                write_f32(&dir.join("incoherent_t_irradia.f32"), &it);
            }
            let hits = |t: &[f32]| t.iter().filter(|x| x.is_finite()).count();
            println!(
                "{{\"renderer\": \"irradia\", \"threads\": {}, \"triangles\": {}, \"bvh_build_s\": {:.4}, \"mesh_build_s\": {:.4}, \"primary_s\": {:.4}, \"primary_mrays\": {:.3}, \"primary_hits\": {}, \"incoherent_s\": {:.4}, \"incoherent_mrays\": {:.3}, \"incoherent_hits\": {}, \"nodes\": {}, \"leaves\": {}, \"max_depth\": {}, \"sah_cost\": {:.2}, \"cpu_s\": {{\"bvh_build\": {:.3}, \"build\": {:.3}, \"primary\": {:.3}, \"incoherent\": {:.3}}}}}",
                rayon::current_num_threads(),
                n_tris,
                bvh_s,
                mesh_s,
                p_s,
                po.len() as f64 / p_s / 1e6,
                hits(&pt),
                i_s,
                io.len() as f64 / i_s / 1e6,
                hits(&it),
                stats.nodes,
                stats.leaves,
                stats.max_depth,
                stats.sah_cost,
                bvh_cpu,
                mesh_cpu,
                c1 - c0,
                c2 - c1
            );
        }
        _ => {
            eprintln!("{usage}");
            std::process::exit(2);
        }
    }
}
